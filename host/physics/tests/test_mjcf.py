"""The exported MJCF read by an independent reader: the official `mujoco` Python package (3.17.0,
installed into .venv by scripts/setup.d/20-mujoco.sh), checked against the model file read by
Python's own tomllib (not by our Rust parser).

Run: .venv/bin/python -m pytest -q host/physics/tests
"""

import pathlib
import subprocess
import tomllib

import mujoco
import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
MODEL = ROOT / "host" / "planner" / "models" / "drosophibot2.toml"


def export(tmp_path, scene):
    out = tmp_path / f"robot-{scene.replace(':', '_')}.xml"
    subprocess.run(
        ["cargo", "run", "--quiet", "--locked", "-p", "dbot", "--bin", "dbot", "--",
         "model", "export", "--model", str(MODEL), "--mjcf", str(out), "--scene", scene],
        cwd=ROOT, check=True)
    return mujoco.MjModel.from_xml_path(str(out))


@pytest.fixture(scope="module")
def toml_model():
    return tomllib.loads(MODEL.read_text())


@pytest.mark.parametrize("scene", ["flat", "incline:10", "ball"])
def test_masses_inertias_axes_limits_equal_the_model_file(tmp_path, toml_model, scene):
    m = export(tmp_path, scene)
    assert mujoco.__version__ == "3.17.0"
    for b in toml_model["body"]:
        i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b["name"])
        assert i >= 0, b["name"]
        assert m.body_mass[i] == pytest.approx(b["mass_kg"], rel=1e-12)
        np.testing.assert_allclose(m.body_ipos[i], b["com_m"], atol=1e-12)
        xx, yy, zz, xy, xz, yz = b["inertia_kg_m2"]
        want = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        r = np.zeros(9)
        mujoco.mju_quat2Mat(r, m.body_iquat[i])
        r = r.reshape(3, 3)
        got = r @ np.diag(m.body_inertia[i]) @ r.T
        np.testing.assert_allclose(got, want, atol=1e-9 * np.linalg.norm(want))
    hinges = 0
    for j in toml_model["joint"]:
        name = f'{j["leg"]}_{j["kind"]}'
        jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)
        if j["actuation"] == "fixed":
            assert jid < 0, f"{name} is fixed in the model file"
            continue
        hinges += 1
        assert jid >= 0, name
        np.testing.assert_allclose(m.jnt_axis[jid], j["axis"], atol=1e-12)
        np.testing.assert_allclose(m.jnt_range[jid], j["limits_rad"], rtol=1e-12)
        a = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, name)
        assert m.actuator_gainprm[a][0] == pytest.approx(j["stiffness_nm_per_rad"], rel=1e-12)
        stall = {"mx28": 2.5, "mx64": 6.0}[j["actuation"]]
        np.testing.assert_array_equal(m.actuator_forcerange[a], [-stall, stall])
    assert hinges == m.nu == 22
    total = sum(b["mass_kg"] for b in toml_model["body"])
    assert m.body_subtreemass[1] == pytest.approx(total, rel=1e-12)


def test_standing_on_flat_ground_the_feet_carry_the_weight(tmp_path, toml_model):
    """MuJoCo alone (no Rust plant): the stance keyframe held by the position actuators, gravity
    ramped in over 1 s; after 3 s the contact normal forces add up to m g within 1 %."""
    m = export(tmp_path, "flat")
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    g = m.opt.gravity.copy()
    while d.time < 3.0:
        m.opt.gravity[:] = g * min(1.0, d.time)
        mujoco.mj_step(m, d)
    normal = 0.0
    for i in range(d.ncon):
        f = np.zeros(6)
        mujoco.mj_contactForce(m, d, i, f)
        normal += f[0]
    weight = sum(b["mass_kg"] for b in toml_model["body"]) * 9.81
    assert d.ncon == 6
    assert normal == pytest.approx(weight, rel=0.01)
