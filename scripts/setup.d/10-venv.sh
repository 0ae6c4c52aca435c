#!/usr/bin/env bash
# Creates the shared Python venv `.venv` at the repo root and installs requirements-dev.txt into it.
# Idempotent: skips pip when the requirements file has not changed since the last install.
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
stamp=.venv/.requirements-dev.sha256
want=$(sha256sum requirements-dev.txt | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r requirements-dev.txt
    echo "$want" > "$stamp"
fi
echo ".venv ready: $(.venv/bin/python -c 'import dynamixel_sdk, serial; print("dynamixel-sdk 4.1.0 (pinned)", "pyserial", serial.__version__)')"
