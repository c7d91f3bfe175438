"""How fast the virtual plant's steering covers every controllable supervisor transition, per example: runs
`codegen run EXAMPLE --events N --seed S --timing T --json` under QEMU for seeds 1..20 (two at a time) and
prints, per example, the median and worst event count at which coverage became full (`incomplete` when a run
never got there) and the steering resets, as `docs/steering.md` records them.

    python3 scripts/measure/steering.py [--events 10000] [--seeds 20] [--timing lockstep] [EXAMPLE ...]

EXAMPLE is a name below or a manifest path (default: every name below). T is `codegen run`'s default,
lockstep, unless told. The codegen binary is target/debug/codegen (build it first: `cargo build -p codegen`).
Exit status 1 when a run did not reach full coverage, or when nothing was measured: no example, no seed,
or no example with a supervisor transition to cover (one without, as livelock, has no supervisor, and
prints `nothing to cover`).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES = {
    "cell": "examples/cell/cell.toml",
    "factory": "examples/factory/factory.toml",
    "livelock": "examples/livelock/livelock.toml",
    "station": "examples/station/station.toml",
    "distribution": "examples/distribution/distribution.toml",
}


def run(codegen, manifest, events, seed, timing):
    """One closed-loop run; its report as a dict."""
    out = subprocess.run(
        [codegen, "run", manifest, "--events", str(events), "--seed", str(seed), "--timing", timing, "--json"],
        cwd=ROOT, capture_output=True, text=True, check=False)
    if out.returncode not in (0, 1):
        sys.exit(f"{manifest} seed {seed}: exit {out.returncode}\n{out.stderr}")
    return json.loads(out.stdout)


def taken(report):
    """Transitions taken out of those reachable, over every supervisor."""
    cover = report["coverage"]
    return f"{sum(c['taken'] for c in cover)}/{sum(c['reachable'] or 0 for c in cover)}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("examples", nargs="*", default=list(EXAMPLES))
    parser.add_argument("--events", type=int, default=10_000)
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--codegen", default=os.path.join(ROOT, "target", "debug", "codegen"))
    parser.add_argument("--timing", default="lockstep", choices=["realtime", "lockstep"])
    args = parser.parse_args()
    if not args.examples or args.seeds < 1:
        sys.exit("steering.py: nothing to measure (no example or no seed)")
    failed = False
    measured = 0
    print(f"{'example':<10} {'full coverage at (median / worst)':>34} {'resets (median / worst)':>24}  incomplete")
    for name in args.examples:
        manifest = EXAMPLES.get(name, name)
        # The first run builds the firmware; the others find it built.
        first = run(args.codegen, manifest, args.events, 1, args.timing)
        with ThreadPoolExecutor(max_workers=2) as pool:
            rest = list(pool.map(lambda s: run(args.codegen, manifest, args.events, s, args.timing),
                                 range(2, args.seeds + 1)))
        reports = [first] + rest
        if not any(sum(c["reachable"] or 0 for c in r["coverage"]) for r in reports):
            print(f"{name:<10} {'nothing to cover (no supervisor transition)':>34}")
            continue
        measured += 1
        at = [r["full_coverage_at"] for r in reports]
        resets = [r["steering_resets"] for r in reports]
        missing = [r["seed"] for r in reports if r["full_coverage_at"] is None]
        for r in reports:
            print(f"  {name} seed {r['seed']}: full coverage at {r['full_coverage_at']}, "
                  f"{taken(r)} transitions taken, {r['steering_resets']} resets, "
                  f"{r['uncontrollable']} plant events, {r['violations']} violations", file=sys.stderr)
        covered = sorted(a for a in at if a is not None)
        median = statistics.median_low(covered) if covered else None
        worst = "incomplete" if missing else max(covered)
        least = min(reports, key=lambda r: sum(c["taken"] for c in r["coverage"]))
        print(f"{name:<10} {str(median) + ' / ' + str(worst):>34} "
              f"{str(statistics.median_low(resets)) + ' / ' + str(max(resets)):>24}  "
              f"{'seeds ' + str(missing) + ', least taken ' + taken(least) if missing else '-'}")
        failed |= bool(missing)
    if not measured:
        sys.exit("steering.py: nothing measured (no example has a supervisor transition to cover)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
