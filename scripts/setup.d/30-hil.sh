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
