"""Committed expected figures, and the comparison that fails a run when a measurement drifts.

An expectations file (`.ci/expected/*.size`, `*.cost`) holds one figure per line:

    # comment
    NAME  VALUE  TOLERANCE  [<= LIMIT]

TOLERANCE is `N%` of VALUE or an absolute `N` (0 = exact). The optional LIMIT is a goal the figure must
never pass, whatever the tolerance. Every name in the file must be measured (a figure that disappears is a
failure, not a pass), and every measured figure must be in the file (a new one is added on purpose).
"""

import os
import re
import subprocess
import sys


class Expected:
    """One line of an expectations file."""

    def __init__(self, name, value, tolerance, percent, limit):
        self.name = name
        self.value = value
        self.tolerance = tolerance
        self.percent = percent
        self.limit = limit

    def allowed(self):
        return self.value * self.tolerance / 100 if self.percent else self.tolerance

    def describe(self):
        tol = f"±{self.tolerance:g}%" if self.percent else f"±{self.tolerance:g}"
        lim = f", goal <= {self.limit:g}" if self.limit is not None else ""
        return f"expected {self.value:g} {tol}{lim}"


LINE = re.compile(r"^(\S+)\s+(\d+(?:\.\d+)?)\s+(\d+(?:\.\d+)?)(%?)(?:\s+<=\s+(\d+(?:\.\d+)?))?\s*$")


def load(path):
    """The expectations of `path`, in file order; a malformed line is an error naming the line."""
    out = []
    with open(path, encoding="utf-8") as f:
        for number, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            m = LINE.match(line)
            if not m:
                sys.exit(f"{path}:{number}: expected 'NAME VALUE TOLERANCE[%] [<= LIMIT]', found '{line}'")
            name, value, tol, pct, limit = m.groups()
            out.append(Expected(name, float(value), float(tol), pct == "%", None if limit is None else float(limit)))
    if not out:
        sys.exit(f"{path}: no expected figures")
    return out


def compiler():
    """The compiler the figures come from, as `rustc -V` prints it."""
    return subprocess.run(["rustc", "-V"], capture_output=True, text=True, check=True).stdout.strip()


def check(path, measured):
    """Prints every figure beside its expectation and exits 1 when one is missing, new, beyond its
    tolerance or over its goal. `measured` maps names to numbers. SCT_WRITE_EXPECTED=1 rewrites `path` with
    the measured values (tolerances and goals kept), for a change made on purpose."""
    expected = load(path)
    names = {e.name for e in expected}
    failures = []
    print(f"figures from {compiler()}, checked against {path}")
    for e in expected:
        if e.name not in measured:
            failures.append(f"{e.name}: not measured ({e.describe()})")
            continue
        got = measured[e.name]
        bad = []
        if abs(got - e.value) > e.allowed():
            bad.append("beyond tolerance")
        if e.limit is not None and got > e.limit:
            bad.append("over the goal")
        mark = "FAIL " + " and ".join(bad) if bad else "ok"
        print(f"  {e.name:<28} {got:>9g}   {e.describe():<36} {mark}")
        if bad:
            failures.append(f"{e.name}: {got:g}, {e.describe()}: {' and '.join(bad)}")
    for name in sorted(set(measured) - names):
        failures.append(f"{name}: measured {measured[name]:g} but not in {path}")
    if os.environ.get("SCT_WRITE_EXPECTED") == "1":
        rewrite(path, measured)
        print(f"rewrote {path} with the measured values")
        return
    if failures:
        print(f"{len(failures)} figure(s) wrong:", file=sys.stderr)
        for f in failures:
            print(f"  {f}", file=sys.stderr)
        print(f"(a change made on purpose: SCT_WRITE_EXPECTED=1 rewrites {path})", file=sys.stderr)
        sys.exit(1)


def rewrite(path, measured):
    """`path` with each figure's value replaced by the measured one; comments, tolerances, goals kept."""
    lines = []
    with open(path, encoding="utf-8") as f:
        for raw in f:
            body, _, comment = raw.rstrip("\n").partition("#")
            m = LINE.match(body.strip())
            value = re.match(r"(\s*\S+\s+)(\S+)(\s*)", body) if m and m.group(1) in measured else None
            if value:
                # The new value in the old one's column, the columns after it where they were.
                text = f"{measured[m.group(1)]:g}"
                width = len(value.group(2)) + len(value.group(3))
                padded = text + " " * max(width - len(text), 1 if value.group(3) else 0)
                raw = value.group(1) + padded + raw.rstrip("\n")[value.end():]
            else:
                raw = raw.rstrip("\n")
            lines.append(raw)
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
