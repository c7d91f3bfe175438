"""Every table layout measured side by side on the cell (docs/layouts.md): per layout, the tables emitted
with `codegen emit examples/cell/cell.toml --layout L`, then on the Cortex-M3 (QEMU lm3s6965evb) the runtime's
code and tables and the instructions per uncontrollable event and per decision (`cargo qemu-cost`, exact
under -icount), and on the emulated RP2040's Cortex-M0+ the Pico image's flash and the instructions per call
(`codegen run --target rp2040 --io pins --layout L`). Prints a Markdown table. `--supervisors` measures another
deployment of the cell (reduced, monolithic, monolithic-reduced: the set `emit` and `run` deploy); with
`--expected FILE` the figures of the one layout measured are checked against FILE (the full set's default
layout is checked by cost.py, footprint.py and pico_cost.py).

    python3 scripts/measure/layouts.py [--layouts ranked,compact] [--pico-events 20000]
    python3 scripts/measure/layouts.py --layouts ranked --supervisors reduced \
        --expected .ci/expected/cell-reduced.txt
"""

import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
import cost  # noqa: E402
import expect  # noqa: E402
import footprint  # noqa: E402
import pico_cost  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
LAYOUTS = ("memory-safe", "offset", "ranked", "indexed", "compact")
# The figures `--expected` compares, per core.
CHECKED = {"m3": ("code+tables", "tables", "runtime_ram", "apply.avg", "apply.max", "decide.avg", "decide.max"),
           "m0": ("flash", "static_ram", "apply.avg", "apply.max", "decide.avg", "decide.max")}


def codegen(args, target_dir):
    """Runs the codegen binary with `args`; returns its stdout."""
    cmd = ["cargo", "run", "--quiet", "-p", "codegen", "--"] + args
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.abspath(target_dir))
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(f"{' '.join(cmd)} exited with {run.returncode}")
    return run.stdout


def measure(layout, supervisors, target_dir, pico_events):
    """The figures of one layout of the `supervisors` deployment: M3 footprint and cost, M0+ flash and cost."""
    tables = os.path.abspath(os.path.join(target_dir, "layouts", f"cell-{supervisors}-{layout}.rs"))
    os.makedirs(os.path.dirname(tables), exist_ok=True)
    deploy = ["--layout", layout, "--supervisors", supervisors]
    codegen(["emit", "examples/cell/cell.toml", *deploy, "-o", tables], target_dir)
    os.environ["SCT_TABLES"] = tables
    try:
        footprint.build(target_dir, [], "qemu-build")
        m3 = footprint.measure(os.path.join(target_dir, "thumbv7m-none-eabi", "release", "cell-qemu"))
        m3.update(cost.parse(footprint.build(target_dir, [], "qemu-cost")))
        footprint.build(target_dir, [], "pico-build")
        rows = footprint.sections(os.path.join(target_dir, "thumbv6m-none-eabi", "release", "cell-pico"))
        m0 = pico_cost.footprint(rows)
    finally:
        del os.environ["SCT_TABLES"]
    report = json.loads(codegen(["run", "--target", "rp2040", "--io", "pins", *deploy, "--events", str(pico_events), "--json"],
                                target_dir))
    m0.update(pico_cost.parse(report))
    return m3, m0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--layouts", default=",".join(LAYOUTS), help="comma-separated layouts to measure")
    ap.add_argument("--supervisors", default="full", help="the deployment: full, reduced, monolithic, "
                    "monolithic-reduced")
    ap.add_argument("--pico-events", type=int, default=20_000, help="events of each RP2040 run")
    ap.add_argument("--expected", help="check the one layout's figures against this expectations file")
    ap.add_argument("--target-dir", help="cargo's target directory for the builds")
    args = ap.parse_args()
    target_dir = args.target_dir or os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    layouts = args.layouts.split(",")
    if args.expected and len(layouts) != 1:
        sys.exit("layouts: --expected checks one layout; name it with --layouts")
    rows = []
    for layout in layouts:
        m3, m0 = measure(layout, args.supervisors, target_dir, args.pico_events)
        rows.append((layout, m3, m0))
        print(f"{layout}: M3 {m3}\n{layout}: M0+ {m0}", file=sys.stderr)
    print("| layout | M3 code + tables (B) | M3 tables | M3 RAM | M3 apply avg / max | M3 decide avg / max "
          "| M0+ flash | M0+ RAM | M0+ apply avg / max | M0+ decide avg / max |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for layout, m3, m0 in rows:
        print(f"| {layout} | {m3['code+tables']} | {m3['tables']} | {m3['runtime_ram']} "
              f"| {m3['apply.avg']} / {m3['apply.max']} | {m3['decide.avg']} / {m3['decide.max']} "
              f"| {m0['flash']} | {m0['static_ram']} | {m0['apply.avg']} / {m0['apply.max']} "
              f"| {m0['decide.avg']} / {m0['decide.max']} |")
    if args.expected:
        _, m3, m0 = rows[0]
        cores = {"m3": m3, "m0": m0}
        expect.check(args.expected, {f"{core}.{name}": cores[core][name]
                                     for core, names in CHECKED.items() for name in names})


if __name__ == "__main__":
    main()
