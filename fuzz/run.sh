#!/usr/bin/env bash
# Runs the protocol's cargo-fuzz targets for a bounded time each (default 60 s):
#   fuzz/run.sh [seconds] [target...]
# Needs the nightly toolchain (present on these machines) and cargo-fuzz, installed here from
# crates.io when missing. Not part of scripts/test.sh: the bounded proptest versions of the same
# checks run there (protocol/tests/robustness.rs).
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(frame_decode gait_table upload)
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
for t in "${targets[@]}"; do
    printf '\n==> fuzz %s for %s s\n' "$t" "$secs"
    cargo +nightly fuzz run "$t" -- -max_total_time="$secs"
done
