#!/usr/bin/env bash
# A longer randomised pass of the workspace's proptests: ROUNDS runs, each with a fresh seed (the
# test command uses the fixed seed of .cargo/config.toml). Usage: scripts/proptest-long.sh [rounds]
# A failing round prints its seed (rerun it with PROPTEST_RNG_SEED=<seed>); failing cases are saved
# beside the test (*.proptest-regressions) and replayed first by every later run: commit them.
set -euo pipefail
cd "$(dirname "$0")/.."
rounds="${1:-20}"
filter='(package(protocol) & test(/^(roundtrip|robustness)::/)) | (package(planner) & test(/^reliability_inputs::/))'
for round in $(seq 1 "$rounds"); do
    seed="$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')"
    echo "==> round $round/$rounds: PROPTEST_RNG_SEED=$seed"
    PROPTEST_RNG_SEED="$seed" cargo nextest run --workspace --locked --release --no-fail-fast \
        --status-level fail -E "$filter"
done
