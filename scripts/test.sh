#!/usr/bin/env bash
# The one test command: installs what a fresh machine lacks, then checks formatting and lints, builds
# the firmware image and prints its budget, and runs every test. `.ci/run` calls exactly this. At the
# end (also after a failure) it prints each step's wall time.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
# The emulator tests (hil-tests, pytest) must run here: a missing prerequisite fails them.
unset DBOT_HIL_OPTIONAL

# Each step's wall time, printed as a table when the script ends, also when a step fails (EXIT trap):
# the failing step is the last row, marked FAILED; then nextest's summary line again, so the output
# still ends with the runner's summary.
step_names=()
step_secs=()
step_start=$SECONDS
# The RP2040 builds' rows (they run beside the others, see below) and their job.
beside_names=()
beside_secs=()
fw_pid=""
fw_dir=""
finish_step() {
    if [ "${#step_names[@]}" -gt 0 ]; then
        step_secs+=($((SECONDS - step_start)))
    fi
}
step() {
    finish_step
    step_names+=("$*")
    step_start=$SECONDS
    printf '\n==> %s\n' "$*"
}
# A job and every process it started (cargo and rustc under the RP2040 builds' subshell).
kill_tree() {
    local child
    for child in $(pgrep -P "$1" || true); do
        kill_tree "$child"
    done
    kill "$1" 2>/dev/null || true
}
print_times() {
    local status=$?
    finish_step
    local n=${#step_names[@]} i mark
    printf '\n==> wall time per step\n'
    printf '%8s  %s\n' "seconds" "step"
    for ((i = 0; i < n; i++)); do
        mark=""
        if [ "$status" -ne 0 ] && [ "$i" -eq $((n - 1)) ]; then mark="   FAILED (exit $status)"; fi
        printf '%8d  %s%s\n' "${step_secs[i]}" "${step_names[i]}" "$mark"
    done
    for ((i = 0; i < ${#beside_names[@]}; i++)); do
        printf '%8d  %s\n' "${beside_secs[i]}" "${beside_names[i]}"
    done
    printf '%8d  %s\n' "$SECONDS" "total (wall)"
    # The output ends with the test runner's summary line, as it would without the table.
    if [ -s "$summary_log" ]; then
        grep -E '^ +Summary ' "$summary_log" | tail -n 1 || true
    fi
    rm -f "$summary_log"
    # A failure before the join: stop the RP2040 builds and show what they printed.
    if [ -n "$fw_pid" ]; then
        kill_tree "$fw_pid"
        wait "$fw_pid" 2>/dev/null || true
        cat "$fw_dir/log" 2>/dev/null || true
    fi
    if [ -n "$fw_dir" ]; then rm -rf "$fw_dir"; fi
}
summary_log=$(mktemp)
trap print_times EXIT

step "toolchain: thumbv6m-none-eabi target, rustfmt, clippy"
rustup target add thumbv6m-none-eabi >/dev/null
rustup component add rustfmt clippy >/dev/null 2>&1 || true

# The RP2040 builds run beside the host's set-up, lints and builds: they lock other build
# directories (target/release and target/thumbv6m-none-eabi for the firmware; hil-tests/on-target
# is its own workspace), and a cargo build leaves a core idle for much of its time (one crate at a
# time on the longest chain of dependencies). Their output goes to a log, printed when they are
# joined before the first step that needs the image (the emulated board); their times are rows of
# the table below, marked "(beside)".
fw_dir=$(mktemp -d)
(
    set -euo pipefail
    fw_step() {
        local name=$1 start=$SECONDS
        shift
        printf '\n==> %s (beside)\n' "$name"
        "$@"
        printf '%s\t%s\n' "$((SECONDS - start))" "$name (beside)" >>"$fw_dir/times"
    }
    fw_step "clippy on the firmware for thumbv6m-none-eabi (-D warnings)" \
        bash -c 'cd firmware && cargo clippy --release --locked -- -D warnings'
    fw_step "firmware release image for thumbv6m-none-eabi" \
        bash -c 'cd firmware && cargo build --release --locked'
    fw_step "on-target tests (hil-tests/on-target, embedded-test) build for thumbv6m-none-eabi" \
        bash -c 'cd hil-tests/on-target && cargo build --tests --locked'
) >"$fw_dir/log" 2>&1 &
fw_pid=$!
# Waits for the RP2040 builds, prints their output and adds their times to the table; fails the
# step if they failed.
join_firmware() {
    local status=0
    wait "$fw_pid" || status=$?
    fw_pid=""
    cat "$fw_dir/log"
    if [ -s "$fw_dir/times" ]; then
        while IFS=$'\t' read -r secs name; do
            beside_names+=("$name")
            beside_secs+=("$secs")
        done <"$fw_dir/times"
    fi
    return "$status"
}

for setup in scripts/setup.d/*.sh; do
    [ -e "$setup" ] || continue
    step "setup: $setup"
    bash "$setup"
done

step "cargo fmt --check"
cargo fmt --all --check

step "clippy on the host crates (-D warnings)"
cargo clippy --workspace --all-targets --locked -- -D warnings

step "the RP2040 builds started at the beginning (joined: their output and times follow)"
join_firmware
cargo run --quiet --locked -p hil-tests --bin firmware-size -- target/thumbv6m-none-eabi/release/firmware

step "emulated board for pytest: hil-emulator and hil-bus (the firmware image is built above)"
cargo build --quiet --locked -p hil-tests --bins

step "the dbot CLI for pytest (plan directories it writes, read from Python)"
cargo build --quiet --locked -p dbot --bin dbot

step "Python package tests (pytest, .venv; closed loop on the virtual robot and the emulated board; exported MJCF read by the mujoco package)"
.venv/bin/python -m pytest -q python/tests host/physics/tests

step "doc tests"
cargo test --workspace --doc --locked

step "every command the docs give to reproduce a figure, in a quick mode (bench/run.sh --quick)"
bench/run.sh --quick

step "all host-side tests (nextest)"
cargo nextest run --workspace --locked --no-fail-fast 2>&1 | tee "$summary_log"
