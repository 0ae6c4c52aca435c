"""Uneven ground in the exported MJCF, read by an independent reader (the official `mujoco`
package) and checked against an independent implementation of the field: SplitMix64 written
here from its definition (Steele, Lea and Flood 2014), the cell's key
splitmix64(seed ^ splitmix64(i << 32 | j)), its top 53 bits over 2^53 times the height, a gap
when the next draw is below the gap fraction (planner/src/terrain/blocks.rs's documented rule).
"""

from __future__ import annotations

import pathlib
import subprocess

import mujoco
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
MASK = (1 << 64) - 1


def splitmix64(state: int) -> int:
    z = (state + 0x9E3779B97F4A7C15) & MASK
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return z ^ (z >> 31)


def unit(x: int) -> float:
    return (x >> 11) / float(1 << 53)


def test_splitmix64_reference_vector() -> None:
    # Vigna's splitmix64.c from state 1234567: first output.
    assert splitmix64(1234567) == 6457827717110365317


@pytest.mark.parametrize("seed", [3, 4])
def test_block_tops_are_the_seeded_field(tmp_path, seed) -> None:
    height, size, gaps = 0.02, 0.05, 0.1
    out = tmp_path / "blocks.xml"
    subprocess.run(
        ["cargo", "run", "--quiet", "--locked", "-p", "dbot", "--bin", "dbot", "--", "model",
         "export", "--model", "drosophibot2", "--mjcf", str(out),
         "--scene", f"blocks:{seed}:{height}:{size}:{gaps}"],
        cwd=ROOT, check=True)
    m = mujoco.MjModel.from_xml_path(str(out))
    nx, ny = 60, 24  # 3 m x 1.2 m of 50 mm cells, from (-0.6, -0.6)
    found = gapped = 0
    for i in range(nx):
        for j in range(ny):
            key = splitmix64(seed ^ splitmix64((i << 32) | j))
            gid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, f"block_{i}_{j}")
            if unit(splitmix64(key)) < gaps:
                assert gid == -1, (i, j)
                gapped += 1
                continue
            top = m.geom_pos[gid][2] + m.geom_size[gid][2]
            assert top == pytest.approx(unit(key) * height, abs=1e-12), (i, j)
            assert m.geom_pos[gid][0] == pytest.approx(-0.6 + (i + 0.5) * size, abs=1e-12)
            found += 1
    assert found + gapped == nx * ny and gapped > 0
