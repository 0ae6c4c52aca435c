#!/usr/bin/env bash
# HIL stage prerequisites: the emulator runner's Node packages (exactly as pinned in
# hil-tests/runner/package-lock.json) and defmt-print to decode the firmware's logs. Idempotent and
# quick when done: npm ci runs only when the lock file changed since the last install.
set -euo pipefail
cd "$(dirname "$0")/../.."

runner=hil-tests/runner
stamp="$runner/node_modules/.lock-installed"
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo "30-hil: node and npm are needed for the emulator runner (Node 20+)" >&2
    exit 1
fi
if [ ! -f "$stamp" ] || ! cmp -s "$runner/package-lock.json" "$stamp"; then
    (cd "$runner" && npm ci --no-audit --no-fund --loglevel=error)
    cp "$runner/package-lock.json" "$stamp"
fi

if ! command -v defmt-print >/dev/null && [ ! -x "${CARGO_HOME:-$HOME/.cargo}/bin/defmt-print" ]; then
    cargo install defmt-print --locked
fi

# elf2flash converts the release image to UF2 for flashing without a probe (docs/hardware.md); the
# test `uf2_image` checks its output against the ELF. It links libudev (Debian: libudev-dev).
if ! elf2flash --version 2>/dev/null | grep -q '^elf2flash 0\.1\.0$'; then
    if ! pkg-config --exists libudev 2>/dev/null; then
        if [ "$(id -u)" = 0 ]; then
            apt-get install -y -q libudev-dev >/dev/null
        else
            echo "30-hil: elf2flash needs libudev's headers: sudo apt-get install libudev-dev" >&2
            exit 1
        fi
    fi
    cargo install elf2flash --version 0.1.0 --locked
fi
