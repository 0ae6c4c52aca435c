"""The build backend of ``pip install ./python``: maturin's, after making sure MuJoCo is there.

The extension links the physics robot (crate ``physics``), which links MuJoCo 3.17.0 from the
folder ``scripts/setup.d/20-mujoco.sh`` fills (``.mujoco/`` at the repository root, named by
``.cargo/config.toml``). On a fresh clone that folder is empty and the Rust build scripts would stop
with a panic and a backtrace; this backend runs the set-up script first (it downloads the official
``mujoco==3.17.0`` wheel from PyPI and unpacks its library), and if that cannot be done stops with
one line naming the script. Every hook is maturin's own.
"""

from __future__ import annotations

import pathlib
import subprocess
import sys

import maturin

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "setup.d" / "20-mujoco.sh"
LIBRARY = ROOT / ".mujoco" / "lib-from-scripts-setup.d-20-mujoco.sh" / "libmujoco.so.3.17.0"


def _ensure_mujoco() -> None:
    """Runs scripts/setup.d/20-mujoco.sh when MuJoCo's library is missing; one line if it fails."""
    if LIBRARY.is_file():
        return
    print(f"dbot: MuJoCo 3.17.0 is missing; running {SCRIPT.relative_to(ROOT)}", file=sys.stderr)
    done = subprocess.run(["bash", str(SCRIPT)], cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0 or not LIBRARY.is_file():
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise SystemExit(
            f"dbot: MuJoCo 3.17.0 could not be installed ({last}); "
            f"run `bash {SCRIPT.relative_to(ROOT)}` from {ROOT}, then pip install again"
        )


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    _ensure_mujoco()
    return maturin.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    _ensure_mujoco()
    return maturin.build_editable(wheel_directory, config_settings, metadata_directory)


def build_sdist(sdist_directory, config_settings=None):
    return maturin.build_sdist(sdist_directory, config_settings)


get_requires_for_build_wheel = maturin.get_requires_for_build_wheel
get_requires_for_build_sdist = maturin.get_requires_for_build_sdist
get_requires_for_build_editable = getattr(
    maturin, "get_requires_for_build_editable", maturin.get_requires_for_build_wheel
)
prepare_metadata_for_build_wheel = maturin.prepare_metadata_for_build_wheel
prepare_metadata_for_build_editable = getattr(
    maturin, "prepare_metadata_for_build_editable", maturin.prepare_metadata_for_build_wheel
)
