#!/usr/bin/env bash
# MuJoCo 3.17.0 for the `physics` crate (host/physics): the shared library and headers of the official
# `mujoco==3.17.0` wheel go into `.mujoco/` (git-ignored) with a `libmujoco.so` symlink, which
# `.cargo/config.toml` points mujoco-rs at (MUJOCO_DYNAMIC_LINK_DIR); host/physics/build.rs adds an rpath
# so binaries and tests find it without LD_LIBRARY_PATH. The same wheel's Python package goes into `.venv`
# as an independent reader of exported MJCF (host/physics/tests/test_mjcf.py).
# 3.17.0 is the release mujoco-rs 7.0.0 binds: change both together. Idempotent and quick when done.
# `--lib-only`: the library and headers alone, no venv (scripts/demo.sh: the demo links the library and
# never runs the Python reader; the venv and its wheel were about 10 s of a fresh clone's demo).
set -euo pipefail
lib_only=0
[ "${1:-}" = "--lib-only" ] && lib_only=1
cd "$(dirname "$0")/../.."

version=3.17.0
dir=.mujoco
# The library folder's name says where it comes from: mujoco-rs's build script prints this path when
# the library is missing, so a fresh clone's build error names this script.
lib="$dir/lib-from-scripts-setup.d-20-mujoco.sh"
so="$lib/libmujoco.so.$version"
if [ ! -f "$so" ] || [ ! -f "$dir/include/mujoco/mujoco.h" ]; then
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    python3 -m pip download --quiet --disable-pip-version-check --no-deps "mujoco==$version" -d "$tmp"
    wheel=$(ls "$tmp"/mujoco-"$version"-*.whl)
    mkdir -p "$dir"
    python3 - "$wheel" "$dir" "$version" <<'PY'
import sys, zipfile, pathlib
wheel, out, version = sys.argv[1], pathlib.Path(sys.argv[2]), sys.argv[3]
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.endswith("/"):
            continue
        if name == f"mujoco/libmujoco.so.{version}":
            target = out / "lib-from-scripts-setup.d-20-mujoco.sh" / name.removeprefix("mujoco/")
        elif name.startswith("mujoco/include/"):
            target = out / name.removeprefix("mujoco/")
        else:
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(z.read(name))
PY
fi
ln -sfn "libmujoco.so.$version" "$lib/libmujoco.so"
if [ "$lib_only" = 1 ]; then
    echo "MuJoCo $version library ready in $lib"
    exit 0
fi

# The Python reader, in the shared venv (10-venv.sh creates it; this keeps the script usable alone).
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
if ! .venv/bin/python -c "import mujoco, sys; sys.exit(mujoco.__version__ != '$version')" 2>/dev/null; then
    .venv/bin/python -m pip install --quiet --disable-pip-version-check "mujoco==$version"
fi
echo "MuJoCo $version ready in $lib (Python: $(.venv/bin/python -c 'import mujoco; print(mujoco.__version__)'))"
