#!/usr/bin/env bash
# The README's first command. `dbot` links the physics robot (MuJoCo 3.17.0), so a fresh machine
# first needs MuJoCo's library (scripts/setup.d/20-mujoco.sh --lib-only: quick when already done); then the
# demo plans the built-in Drosophibot II's tripod gait (the servo-safe preset: table 1 at a 1.0 s
# swing), uploads it and walks it on the physics robot (a MuJoCo body under the firmware's library;
# `--port virtual` for the virtual robot without a body), no hardware.
# Extra arguments go to `dbot demo` (e.g. --port physics).
# Built with the `quick-release` profile (Cargo.toml: release without LTO and debug info), which
# builds quicker from a fresh clone; docs/performance.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.d/20-mujoco.sh --lib-only
exec cargo run --profile quick-release --locked --bin dbot -- demo "$@"
