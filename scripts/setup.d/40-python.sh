#!/usr/bin/env bash
# The Python side: pinned maturin, numpy, pytest, matplotlib and gymnasium (dbot.env) in the shared repo-root venv `.venv`,
# then the `dbot` package (python/, PyO3) built and installed into it with `maturin develop`.
# Idempotent: pip skips pinned packages already present, cargo rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/../.."

# 10-venv.sh creates the venv; this keeps the script usable on its own as well.
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi

# numpy 2.4.x is the last series for CPython 3.11 (2.5 needs 3.12). sns-toolbox is not installed:
# it imports torch at module level, see examples/README.md. ray (dbot.sweep's rollouts over a
# cluster): a 79 MB wheel, 240 MB installed, about 20 s to install here (measured 18 s). cma
# (pycma, CMA-ES with NumPy only: python/examples/learn_residual.py; torch is not installed, its
# wheels here are the multi-GB CUDA build). mypy: its stubtest checks python/dbot/_native.pyi
# against the built module (python/tests/test_stubs.py).
.venv/bin/python -m pip install --quiet --disable-pip-version-check \
    maturin==1.16.0 numpy==2.4.6 pytest==9.2.0 matplotlib==3.11.2 gymnasium==1.4.0 ray==2.60.0 \
    cma==4.5.0 mypy==2.4.1

# The quick-release profile (Cargo.toml): optimised like release without LTO, and shared with
# scripts/demo.sh's build of dbot. A debug build of the package ran the tests 4.4 times slower
# (docs/performance.md, "Build and test times").
VIRTUAL_ENV="$PWD/.venv" PATH="$PWD/.venv/bin:$PATH" \
    .venv/bin/maturin develop --quiet --profile quick-release -m python/Cargo.toml
.venv/bin/python -c 'import dbot; print("dbot", dbot.__version__, "installed in .venv")'
