"""Where a single environment's step goes (issue 38 item 2, docs/performance.md): steps
`VectorEnv(1, threads=0)` (or `DbotEnv` with `--dbot-env`) under `perf record`, then attributes
each sample to a part of the step by the innermost frame of its call stack that names one.

    perf record -F 1000 --call-graph dwarf,16384 -o /tmp/step.data \\
        .venv/bin/python bench/step_profile.py run
    perf script -i /tmp/step.data | .venv/bin/python bench/step_profile.py attribute

`run` steps 20 000 times (actions computed beforehand, BLAS pinned to one thread); the setup
(imports, the first reset) is in the samples too, about 3 % of them. Needs the package built
optimised (`maturin develop --profile quick-release`). The parts are matched by symbol, so an
inlined function counts for its caller.

The same step in instructions, which do not depend on the machine's load (callgrind, about a
minute): MuJoCo's own against the rest, per bus cycle,

    valgrind --tool=callgrind --callgrind-out-file=/tmp/step.cg --collect-atstart=no \
        --toggle-collect='_native::vector::VectorCore::__pymethod_step_env__' \
        .venv/bin/python bench/step_profile.py run --steps 1200
    callgrind_annotate --inclusive=yes --tree=calling /tmp/step.cg \
        | .venv/bin/python bench/step_profile.py instructions

(only `VectorCore.step_env` is counted: the first step also runs the first reset's settling,
whose bus cycles are counted as cycles). An instruction of MuJoCo's vectorised solver does more
than one of the byte-wise bus code, so shares of instructions are not shares of time.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import re  # noqa: E402
import sys  # noqa: E402

#: (part, pattern on a frame's symbol or library), tried on each frame from the innermost out.
PARTS = [
    ("MuJoCo (mj_step, with the libc and libm it calls)", r"libmujoco|^mj_step$|^mj_"),
    ("servo drive law per MuJoCo step (Plant::step)", r"physics::plant::Plant::step|physics::drive"),
    ("strain gauges (cut wrenches every 24 ms)", r"StrainSampler|physics::gauges|planner::strain"),
    ("servos' goals and gains in, body state out (before_cycle)",
     r"ServoDynamics>::before_cycle|push_state|figures::Monitor"),
    ("firmware bus cycle on the simulated wire (block_on)", r"SimWire::block_on|run_cycle"),
    ("firmware telemetry out", r"drain_telemetry"),
    ("firmware link receive (the setpoint)", r"VirtualRobot<S>::receive|VirtualTransport.*::send"),
    ("host: Board's record dicts (Python's dbot.Board)", r"_native::board::|_native::records::|_native::body::"),
    ("host link: parse proprioception", r"Board<T>::next_message|link::stream::.*proprioception"),
    ("host link: encode setpoint", r"send_setpoint|setpoint_from_si"),
    ("VectorCore: rows to NumPy, dicts", r"VectorCore|_native::vector::"),
    ("VectorCore: sub-environment step", r"vector_sub::"),
]


def run(steps: int, dbot_env: bool) -> None:
    import numpy as np

    from dbot.env import DbotEnv, VectorEnv

    if dbot_env:
        env = DbotEnv("physics", max_episode_steps=steps + 10)
        env.reset(seed=0)
        acts = [env.rest_rad + 0.02 * np.sin(k * 0.05 + np.arange(22)) for k in range(steps)]
    else:
        env = VectorEnv(1, threads=0, max_episode_steps=steps + 10)
        env.reset(seed=0)
        rest = env.rest_rad.copy()
        acts = [rest + 0.02 * np.sin(k * 0.05 + np.arange(22)) for k in range(steps)]
    for a in acts:
        env.step(a)
    env.close()


def attribute(lines: collections.abc.Iterable[str]) -> None:
    parts = [(name, re.compile(p)) for name, p in PARTS]
    counts: collections.Counter[str] = collections.Counter()
    total = 0
    stack: list[tuple[str, str]] = []

    def flush() -> None:
        nonlocal total
        if not stack:
            return
        total += 1
        for sym, lib in stack:
            for name, r in parts:
                if r.search(sym) or r.search(lib):
                    counts[name] += 1
                    return
        inner = next((lib for _, lib in stack if lib != "inlined"), "")
        if "python" in inner or not inner:
            counts["CPython (the wrapper, the script, the imports)"] += 1
        elif "multiarray" in inner or "numpy" in inner:
            counts["NumPy"] += 1
        else:
            counts["other: " + inner.rsplit("/", 1)[-1]] += 1

    frame = re.compile(r"\s+[0-9a-f]+\s+(.*)\s+\((.*)\)$")
    for line in lines:
        line = line.rstrip("\n")
        if not line.strip():
            flush()
            stack = []
            continue
        m = frame.match(line)
        if m:
            stack.append((m.group(1), m.group(2)))
    flush()
    print(f"| part of the step | share of {total} samples |")
    print("|---|---|")
    for name, n in counts.most_common():
        print(f"| {name} | {100 * n / total:.1f} % |")


def instructions(lines: collections.abc.Iterable[str]) -> None:
    """Totals of `callgrind_annotate --inclusive=yes --tree=calling`: all, MuJoCo's `mj_step`,
    the rest, per bus cycle (the calls of the physics robot's `before_cycle`)."""
    count = lambda text: int(text.replace(",", ""))  # noqa: E731
    total = mj = cycles = None
    for line in lines:
        if "PROGRAM TOTALS" in line:
            total = count(line.split()[0])
        elif re.search(r"\*\s+\S*:mj_step \[", line):
            mj = count(line.split()[0])
        elif cycles is None and re.search(r">\s+.*ServoDynamics>::before_cycle \(", line):
            cycles = count(re.search(r"\(([0-9,]+)x\)", line).group(1))
    if total is None or mj is None or not cycles:
        raise SystemExit("not callgrind_annotate --inclusive=yes --tree=calling of a `run`")
    print(f"| instructions (callgrind, {cycles} bus cycles) | all | per bus cycle |")
    print("|---|---|---|")
    print(f"| the step (`VectorCore.step_env`) | {total:,} | {total // cycles:,} |")
    print(f"| MuJoCo (`mj_step`) | {mj:,} | {mj // cycles:,} |")
    print(f"| the rest: firmware, bus, link, Python | {total - mj:,} | {(total - mj) // cycles:,} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mode", choices=["run", "attribute", "instructions"])
    ap.add_argument("--steps", type=int, default=20_000)
    ap.add_argument("--dbot-env", action="store_true", help="step DbotEnv instead")
    a = ap.parse_args()
    if a.mode == "run":
        run(a.steps, a.dbot_env)
    elif a.mode == "instructions":
        instructions(sys.stdin)
    else:
        attribute(sys.stdin)
    return 0


if __name__ == "__main__":
    sys.exit(main())
