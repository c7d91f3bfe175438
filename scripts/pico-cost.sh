#!/usr/bin/env bash
# Cost of the runtime on the Pico's Cortex-M0+ and the Pico build's footprint, measured on the emulated
# RP2040 (harness/rp2040): the cell closed loop, 20 000 events with edge interrupts, the harness counting
# core cycles and instructions from each entry to each return of the runtime's `apply` (one uncontrollable
# event) and `decide` (a decision that fired a command: enabled set, choice, guard, firing), interrupt
# handlers that preempt them left out; flash and RAM from llvm-size of `cargo pico-build`. Each figure is
# compared with scripts/pico-cost.expected: an average or a size more than 10 % away from it fails, a worst
# case more than 10 % above it (the run's event mix depends on the host's timing: averages move by a few
# per cent, and a run need not meet the worst path — a round of the random local queue restarting, a
# reseed from the ring oscillator every 1024 draws — so a lower worst case passes).
#
#   bash scripts/pico-cost.sh            # measure and compare
#   bash scripts/pico-cost.sh --update   # measure and rewrite the expected figures
set -euo pipefail
cd "$(dirname "$0")/.."

expected=scripts/pico-cost.expected
tolerance=10
target_dir="${CARGO_TARGET_DIR:-target}"
bin="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin"

cargo pico-build --quiet
read -r text data bss < <("$bin/llvm-size" "$target_dir/thumbv6m-none-eabi/release/cell-pico" | awk 'NR == 2 { print $1, $2, $3 }')
json="$(cargo run --quiet --release -p codegen -- run --target rp2040 --events 20000 --json)"

PICO_COST_JSON="$json" FLASH=$((text + data)) RAM=$((data + bss)) RUSTC="$(rustc --version)" \
python3 - "$expected" "$tolerance" "${1:-}" <<'PY'
import json, os, sys

expected_file, tolerance, mode = sys.argv[1], float(sys.argv[2]), sys.argv[3]
report = json.loads(os.environ["PICO_COST_JSON"])
cost = report["board"]["cost"]
measured = {
    "apply_avg_instructions": cost["apply"]["avg_instructions"],
    "apply_max_instructions": cost["apply"]["max_instructions"],
    "decision_avg_instructions": cost["decision"]["avg_instructions"],
    "decision_max_instructions": cost["decision"]["max_instructions"],
    "apply_avg_cycles": cost["apply"]["avg_cycles"],
    "apply_max_cycles": cost["apply"]["max_cycles"],
    "decision_avg_cycles": cost["decision"]["avg_cycles"],
    "decision_max_cycles": cost["decision"]["max_cycles"],
    "flash_bytes": int(os.environ["FLASH"]),
    "ram_bytes": int(os.environ["RAM"]),
}
# The Cortex-M3's instruction counts (README, `cargo qemu-cost`), for the ratio.
m3 = {"apply_avg_instructions": 166, "apply_max_instructions": 248,
      "decision_avg_instructions": 320, "decision_max_instructions": 520}
print(f"{os.environ['RUSTC']}; cell, {report['events']} events, {report['board']['sampling']} sampling, "
      f"{cost['apply']['calls']} applies, {cost['decision']['calls']} decisions measured")
if mode == "--update":
    with open(expected_file, "w") as f:
        f.write("# Expected figures of scripts/pico-cost.sh (the cell on the emulated RP2040); "
                "rewrite with --update (keep the highest worst cases seen).\n")
        f.write(f"# {os.environ['RUSTC']}\n")
        for k, v in measured.items():
            f.write(f"{k} {v}\n")
    print(f"wrote {expected_file}")
expected = {}
for line in open(expected_file):
    if line.strip() and not line.startswith("#"):
        k, v = line.split()
        expected[k] = float(v)
failed = False
print(f"{'figure':28} {'measured':>10} {'expected':>10} {'vs M3':>7}")
for k, v in measured.items():
    e = expected.get(k)
    above = e is None or v > e * (1 + tolerance / 100)
    below = e is not None and v < e * (1 - tolerance / 100) and "_max_" not in k
    off = above or below
    failed |= off
    ratio = f"{v / m3[k]:.2f}x" if k in m3 else ""
    print(f"{k:28} {v:>10} {e if e is not None else '-':>10} {ratio:>7}{'  <- beyond ' + str(tolerance) + ' %' if off else ''}")
sys.exit(1 if failed else 0)
PY
