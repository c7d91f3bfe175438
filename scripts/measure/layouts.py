"""Every table layout measured side by side on the cell (docs/layouts.md): per layout, the tables emitted
with `codegen emit examples/cell/cell.toml --layout L`, then on the Cortex-M3 (QEMU lm3s6965evb) the runtime's
code and tables and the instructions per uncontrollable event and per decision (`cargo qemu-cost`, exact
under -icount), and on the emulated RP2040's Cortex-M0+ the Pico image's flash and the instructions per call
(`codegen run --target rp2040 --layout L`). Prints a Markdown table; checks nothing (the default layout's
figures are checked by cost.py, footprint.py and pico_cost.py).

    python3 scripts/measure/layouts.py [--layouts ranked,compact] [--pico-events 20000]
"""

import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
import cost  # noqa: E402
import footprint  # noqa: E402
import pico_cost  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
LAYOUTS = ("memory-safe", "offset", "ranked", "indexed", "compact")


def codegen(args, target_dir):
    """Runs the codegen binary with `args`; returns its stdout."""
    cmd = ["cargo", "run", "--quiet", "-p", "codegen", "--"] + args
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.abspath(target_dir))
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(f"{' '.join(cmd)} exited with {run.returncode}")
    return run.stdout


def measure(layout, target_dir, pico_events):
    """The figures of one layout: M3 footprint and cost, M0+ flash and cost."""
    tables = os.path.abspath(os.path.join(target_dir, "layouts", f"cell-{layout}.rs"))
    os.makedirs(os.path.dirname(tables), exist_ok=True)
    codegen(["emit", "examples/cell/cell.toml", "--layout", layout, "-o", tables], target_dir)
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
    report = json.loads(codegen(["run", "--target", "rp2040", "--layout", layout, "--events", str(pico_events),
                                 "--json"], target_dir))
    m0.update(pico_cost.parse(report))
    return m3, m0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--layouts", default=",".join(LAYOUTS), help="comma-separated layouts to measure")
    ap.add_argument("--pico-events", type=int, default=20_000, help="events of each RP2040 run")
    ap.add_argument("--target-dir", help="cargo's target directory for the builds")
    args = ap.parse_args()
    target_dir = args.target_dir or os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    rows = []
    for layout in args.layouts.split(","):
        m3, m0 = measure(layout, target_dir, args.pico_events)
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


if __name__ == "__main__":
    main()
