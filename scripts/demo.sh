#!/usr/bin/env bash
# The README's first command. `dbot` links the physics robot (MuJoCo 3.17.0), so a fresh machine
# first needs MuJoCo's library (scripts/setup.d/20-mujoco.sh: quick when already done); then the
# demo plans, uploads and walks the built-in Drosophibot II on the virtual robot (no hardware).
# Extra arguments go to `dbot demo` (e.g. --port physics). Built with the `quick-release` profile (Cargo.toml:
# release without LTO and debug info), which builds quicker from a fresh clone; docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.d/20-mujoco.sh
exec cargo run --profile quick-release --locked --bin dbot -- demo "$@"
