#!/usr/bin/env bash
# Runs the cargo-fuzz targets for a bounded time each (default 60 s), niced, one after another:
#   fuzz/run.sh [seconds] [target...]
# Targets: frame_decode gait_table upload (protocol), dxl_status (Dynamixel status parser),
# model_toml (model TOML loader), aproj (AnimatLab importer), plan_params (planner parameters).
# Seeds: the new targets start from valid inputs (the repo's model files without comments, notes
# and sources, numbers to 6 significant digits (fuzz/seeds/model_toml), the three AnimatLab
# projects stripped to what the importer reads (fuzz/seeds/aproj, made by fuzz/seeds/strip_aproj.py
# from ../shared), a parameter file, the e-manual's ping status packet). Targets with a dictionary
# in fuzz/dicts/ run with it. DBOT_FUZZ_CMIN=1 minimises the corpus after the run (cargo fuzz cmin).
# Needs the nightly toolchain and cargo-fuzz (installed here from crates.io when missing). Not part
# of scripts/test.sh: the bounded proptest versions of the same checks run there
# (protocol/tests/integration/robustness.rs, host/planner/tests/integration/reliability_inputs.rs). Figures: docs/reliability.md.
set -euo pipefail
cd "$(dirname "$0")"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(frame_decode gait_table upload dxl_status model_toml aproj plan_params)
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked

seed() {
    local t="$1"
    mkdir -p "corpus/$t"
    [ -z "$(ls -A "corpus/$t")" ] || return 0
    case "$t" in
        model_toml) cp seeds/model_toml/*.toml "corpus/$t/" ;;
        aproj) cp seeds/aproj/*.aproj "corpus/$t/" ;;
        plan_params)
            printf 'swing_s = 0.5\nduty = 0.6\ngait = { phi_i = 0.5, phi_c = 0.5 }\nslices = 40\nterrain = "ball:0.1:0.02"\nstep_height_m = { hind = 0.02, middle = 0.02, front = 0.02 }\n' \
                >"corpus/$t/seed.toml" ;;
        # First byte: chunk size 3; then the ping status of ID 1 from the e-manual.
        dxl_status) printf '\x03\xFF\xFF\xFD\x00\x01\x07\x00\x55\x00\x06\x04\x26\x65\x5D' >"corpus/$t/ping" ;;
    esac
}

for t in "${targets[@]}"; do
    seed "$t"
    printf '\n==> fuzz %s for %s s\n' "$t" "$secs"
    dict=()
    [ -f "dicts/$t.dict" ] && dict=(-dict="dicts/$t.dict")
    nice -n 19 cargo +nightly fuzz run "$t" "corpus/$t" -- -max_total_time="$secs" -print_final_stats=1 "${dict[@]}"
    if [ "${DBOT_FUZZ_CMIN:-0}" = 1 ]; then
        nice -n 19 cargo +nightly fuzz cmin "$t" "corpus/$t"
    fi
done
