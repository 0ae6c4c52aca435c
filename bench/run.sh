#!/usr/bin/env bash
# The one bench command (issue 12): ours vs SciPy SLSQP, Clarabel (Python), a NumPy reduced solve
# with Pinocchio's RNEA, Pinocchio's RNEA on one leg, a Python reference IK, and the firmware's
# simulated bus cycle vs the wire limit, all on the same inputs in one run. Prints the ratio table;
# everything (export.json, URDFs, results.json, logs) lands in bench/out/.
#
# Usage: bench/run.sh [--slsqp-slices N] [--no-scaling] [--no-firmware] [--firmware-log FILE]
#        bench/run.sh --quick
#   --firmware-log FILE: use the output of an earlier run of the firmware's simulated-wire test
#   (e.g. on a branch that has it) instead of running it here.
#   --quick: the Rust half only, in the dev profile, into a scratch directory: bench_export and
#   every criterion bench the docs cite, each run once (criterion's test mode), and the physics robot bench
#   in both modes on one short walk, and bench/env_steps.py (DbotEnv steps/s, rollouts/s) and
#   bench/vector_env.py (VectorEnv, resets, Ray against processes) briefly. No figures: it
#   checks that the commands still run. scripts/test.sh runs it, so they cannot rot unseen (the
#   removed bench_schur example broke this script for a while).
set -euo pipefail
cd "$(dirname "$0")/.."
SLSQP_SLICES=5
SCALING=--scaling
FIRMWARE=1
FW_GIVEN=""
QUICK=0
while [ $# -gt 0 ]; do
  case "$1" in
    --slsqp-slices) SLSQP_SLICES="$2"; shift 2 ;;
    --no-scaling) SCALING=""; shift ;;
    --no-firmware) FIRMWARE=0; shift ;;
    --firmware-log) FIRMWARE=0; FW_GIVEN="$2"; shift 2 ;;
    --quick) QUICK=1; shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
TARGET_DIR=$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')

if [ "$QUICK" = 1 ]; then
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
  echo "== quick: bench_export (dev profile, no scaling study)" >&2
  cargo build --quiet --locked -p planner --example bench_export
  "$TARGET_DIR/debug/examples/bench_export" "$OUT" --quick >/dev/null
  [ -s "$OUT/export.json" ] || { echo "bench_export wrote no export.json" >&2; exit 1; }
  echo "== quick: criterion benches once each (cargo bench -p planner --bench dynamics / ik; -p dynamixel --bench cycle)" >&2
  cargo test --quiet --locked -p planner --bench dynamics --bench ik
  cargo test --quiet --locked -p dynamixel --features std --bench cycle
  echo "== quick: the physics robot bench, both modes, one short walk each (cargo bench -p physics --bench physics_robot)" >&2
  REPEATS=1 CYCLES=1 cargo test --quiet --locked -p physics --bench physics_robot >/dev/null
  DT=0.001 CYCLES=1 cargo test --quiet --locked -p physics --bench physics_robot >/dev/null
  echo "== quick: the research environment's throughput, 200 steps and 2 rollouts (.venv/bin/python bench/env_steps.py --quick)" >&2
  .venv/bin/python bench/env_steps.py --quick >/dev/null
  echo "== quick: many robots at once, 200 steps, 4 rollouts over a process pool and Ray (.venv/bin/python bench/vector_env.py --quick)" >&2
  .venv/bin/python bench/vector_env.py --quick >/dev/null
  echo "bench/run.sh --quick: every reproduction command ran" >&2
  exit 0
fi

OUT=bench/out
mkdir -p "$OUT"

# Python peers from pinned versions, in a local virtual environment.
if [ ! -x bench/.venv/bin/python ] || ! cmp -s bench/requirements.txt bench/.venv/requirements.txt; then
  python3 -m venv bench/.venv
  bench/.venv/bin/pip install --quiet --disable-pip-version-check -r bench/requirements.txt
  cp bench/requirements.txt bench/.venv/requirements.txt
fi

# Every peer on one thread, like ours (a multi-threaded BLAS on a shared machine also makes SLSQP
# hundreds of times slower through oversubscription).
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 RAYON_NUM_THREADS=1

echo "== ours: build and export (cargo --release)" >&2
cargo build --release --quiet -p planner --example bench_export
TARGET_DIR=$(cargo metadata --format-version 1 --no-deps | bench/.venv/bin/python -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')
"$TARGET_DIR/release/examples/bench_export" "$OUT" $SCALING

FW_LOG="$FW_GIVEN"
if [ "$FIRMWARE" = 1 ]; then
  if grep -qs "fn bus_rate_and_jitter_at_1_and_4_mbps" firmware/tests/walk_on_the_wire.rs; then
    echo "== firmware: simulated-wire bus cycle test" >&2
    FW_LOG="$OUT/firmware_bus.log"
    cargo test --quiet -p firmware --test walk_on_the_wire bus_rate_and_jitter_at_1_and_4_mbps -- --nocapture >"$FW_LOG" 2>&1 || {
      echo "firmware bus test failed, see $FW_LOG" >&2; FW_LOG=""; }
  else
    echo "== firmware: no simulated-wire bus test (firmware/tests/walk_on_the_wire.rs); rates not measured" >&2
  fi
fi

echo "== peers (Python)" >&2
bench/.venv/bin/python bench/peers.py "$OUT" --slsqp-slices "$SLSQP_SLICES" ${FW_LOG:+--firmware "$FW_LOG"} | tee "$OUT/table.txt"
