#!/usr/bin/env python3
"""Makes the model_toml fuzz seeds (fuzz/seeds/model_toml/) from the built-in models: the same
bodies, joints and feet without comments, the `notes` text and the `source` lines, and numbers
with more than 6 decimals rounded to 6 significant digits, so each mutation parses less text.
host/planner/tests/integration/reliability_inputs.rs (valid_inputs_pass_the_checks) checks that they load.

Usage (from the repository root): python3 fuzz/seeds/strip_model_toml.py
"""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "fuzz/seeds/model_toml"


def strip(text: str) -> str:
    text = re.sub(r'(?ms)^notes = """.*?"""\n', "", text)
    lines = [l for l in text.splitlines(keepends=True) if not l.startswith(("#", "source = "))]
    text = "".join(lines)
    return re.sub(
        r"-?\d+\.\d{7,}(?:e-?\d+)?", lambda m: repr(float("%.6g" % float(m.group(0)))), text
    )


def main() -> None:
    OUT.mkdir(exist_ok=True)
    for src in sorted((ROOT / "host/planner/models").glob("*.toml")):
        out = OUT / src.name
        out.write_text(strip(src.read_text()))
        print(f"{src.name}: {src.stat().st_size} -> {out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
