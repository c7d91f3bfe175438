"""Instructions the runtime spends per uncontrollable event and per controllable decision on the cell's
tables, on a Cortex-M3 under `qemu-system-arm -icount shift=7,sleep=off` (`cargo qemu-cost`; the binary,
apps/cell/src/bin/cost_qemu.rs, says how it measures). Every line the figures come from must be present and
the calibration must hold, or the run fails; the figures are compared with `.ci/expected/cell-qemu.cost`.

    python3 scripts/measure/cost.py
"""

import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(__file__))
import expect  # noqa: E402
from footprint import build  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))

# name in the figures -> the line's label in the binary's output
STATS = {
    "apply": "uncontrollable event (apply)",
    "decide": "controllable decision (enabled + choose + guard + fire)",
    "enabled": "enabled set alone",
    "idle_decide": "decision with nothing enabled",
}
STAT = re.compile(r"^\s*(?P<label>[^:]+): n=(?P<n>\d+) avg=\d+ ticks \(~(?P<avg>\d+) instructions\) "
                  r"max=\d+ ticks \(~(?P<max>\d+) instructions\)$")
CALIBRATION = re.compile(r"^calibration: 2000 instructions = (\d+) ticks$")
COUNTERS = re.compile(r"^events in (\d+), commands out (\d+), unexpected (\d+)$")
# One instruction is 2^7 ns under -icount shift=7 and a SysTick tick 1/12 µs: 2 000 instructions = 3 200 ticks.
TICKS_PER_2000 = 3200


def parse(text):
    """The figures of one `cargo qemu-cost` output; exits naming what is missing or wrong."""
    figures, problems = {}, []
    stats = {}
    calibration = counters = None
    for line in text.splitlines():
        if m := STAT.match(line):
            stats[m["label"].strip()] = (int(m["n"]), int(m["avg"]), int(m["max"]))
        elif m := CALIBRATION.match(line):
            calibration = int(m[1])
        elif m := COUNTERS.match(line):
            counters = tuple(int(x) for x in m.groups())
    for name, label in STATS.items():
        if label not in stats:
            problems.append(f"no line for '{label}'")
            continue
        n, avg, mx = stats[label]
        if n == 0:
            problems.append(f"'{label}' measured nothing (n=0)")
        figures[f"{name}.avg"] = avg
        if name in ("apply", "decide"):
            figures[f"{name}.max"] = mx
    if calibration is None:
        problems.append("no calibration line")
    elif abs(calibration - TICKS_PER_2000) > 8:
        problems.append(f"calibration {calibration} ticks for 2000 instructions, expected {TICKS_PER_2000}: "
                        "QEMU is not running with -icount shift=7")
    if counters is None:
        problems.append("no counters line")
    elif counters[2] != 0:
        problems.append(f"{counters[2]} unexpected events: the runtime disagrees with the tables")
    if problems:
        sys.exit("cost: " + "; ".join(problems))
    return figures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--target-dir", help="cargo's target directory for the build")
    ap.add_argument("--cargo-config", action="append", default=[], help="a `--config` for the build")
    args = ap.parse_args()
    target_dir = args.target_dir or os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    out = build(target_dir, args.cargo_config, "qemu-cost")
    sys.stdout.write(out)
    figures = parse(out)
    expect.check(os.path.join(ROOT, ".ci", "expected", "cell-qemu.cost"), figures)


if __name__ == "__main__":
    main()
