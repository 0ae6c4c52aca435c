"""The build backend of ``pip install ./python``: maturin's, after making sure MuJoCo is there.

The extension links the physics robot (crate ``physics``), which links MuJoCo 3.17.0 from the
folder ``scripts/setup.d/20-mujoco.sh`` fills (``.mujoco/`` at the repository root, named by
``.cargo/config.toml``). On a fresh clone that folder is empty and the Rust build scripts would stop
with a panic and a backtrace; this backend runs the set-up script first (it downloads the official
``mujoco==3.17.0`` wheel from PyPI and unpacks its library), and if that cannot be done stops with
one line naming the script. A MuJoCo of one's own is used when ``MUJOCO_DYNAMIC_LINK_DIR`` names
its folder. Every hook is maturin's own.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import maturin

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "setup.d" / "20-mujoco.sh"
LIBRARY = ROOT / ".mujoco" / "lib-from-scripts-setup.d-20-mujoco.sh" / "libmujoco.so.3.17.0"
# A MuJoCo of one's own: cargo's [env] (.cargo/config.toml) does not override a variable already set,
# so the Rust build links the library in this folder instead of .mujoco/.
OWN_DIR = "MUJOCO_DYNAMIC_LINK_DIR"


def _ensure_mujoco() -> None:
    """Runs scripts/setup.d/20-mujoco.sh when MuJoCo's library is missing; one line if it fails.

    With MUJOCO_DYNAMIC_LINK_DIR set, the library must be in that folder (the script installs into
    .mujoco/, which the build would not read): if it is not, one line says so, nothing runs."""
    script = SCRIPT.relative_to(ROOT)
    own = os.environ.get(OWN_DIR)
    if own:
        if (pathlib.Path(own) / LIBRARY.name).is_file():
            return
        raise SystemExit(
            f"dbot: {OWN_DIR}={own} has no {LIBRARY.name}; point it at MuJoCo 3.17.0's library "
            f"folder, or unset it so that `bash {script}` (run by this build) installs MuJoCo"
        )
    if LIBRARY.is_file():
        return
    print(f"dbot: MuJoCo 3.17.0 is missing; running {script}", file=sys.stderr)
    try:
        done = subprocess.run(["bash", str(SCRIPT)], cwd=ROOT, capture_output=True, text=True)
    except OSError as err:  # no bash
        last, code = str(err), 1
    else:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        code = done.returncode
    if code != 0 or not LIBRARY.is_file():
        if code == 0:
            last = f"it ended without {LIBRARY.relative_to(ROOT)}"
        raise SystemExit(
            f"dbot: MuJoCo 3.17.0 could not be installed ({last}); "
            f"run `bash {script}` from {ROOT}, then pip install again"
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
