"""Cost of the runtime on the Raspberry Pi Pico's Cortex-M0+ and the Pico build's footprint, measured on the
emulated RP2040 (harness/rp2040): the cell closed loop, 20 000 events with GPIO edge interrupts, the harness
counting core cycles and instructions from each entry to each return of the runtime's `apply` (one
uncontrollable event) and `decide` (a decision that fired a command: enabled set, choice, guard, firing),
interrupt handlers that preempt them left out; flash and static RAM from the sections of `cargo pico-build`,
whose image must be linked for the RP2040. The figures are compared with `.ci/expected/cell-pico.cost`.

    python3 scripts/measure/pico_cost.py

The run's event mix follows the host's timing, so the averages move by a per cent or two from run to run; the
worst apply and the worst decision are the tables' heaviest paths, which every run meets (a reseed of the
random generator costs the decision that draws it about 13 instructions: the firmware gathers its
ring-oscillator bits while idle).
"""

import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
import expect  # noqa: E402
from footprint import build, sections  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
# RP2040 (Pico): the second-stage bootloader at the start of the XIP flash window, the application's
# vector table after it; 2 MiB of flash, 264 KiB of SRAM.
BOOT2 = 0x1000_0000
VECTORS = 0x1000_0100
FLASH = (0x1000_0000, 2 * 1024 * 1024)
RAM = (0x2000_0000, 264 * 1024)
EVENTS = 20_000


def check_memory(elf, rows):
    """Fails unless boot2 and the vector table are where the RP2040's boot looks for them and every section
    lies in its flash or SRAM: an image linked for another chip would otherwise be measured as this one."""
    def inside(addr, size, region):
        return region[0] <= addr and addr + size <= region[0] + region[1]

    at = {name: addr for name, addr, _ in rows}
    if at.get(".boot2") != BOOT2 or at.get(".vector_table") != VECTORS:
        sys.exit(f"pico cost: {elf}: .boot2 at {at.get('.boot2', 0):#x}, .vector_table at "
                 f"{at.get('.vector_table', 0):#x}: not linked for the RP2040 ({BOOT2:#x}, {VECTORS:#x})")
    for name, addr, size in rows:
        if size and addr and not (inside(addr, size, FLASH) or inside(addr, size, RAM)):
            sys.exit(f"pico cost: {elf}: section {name} at {addr:#x} is outside the RP2040's flash and SRAM")


def footprint(rows):
    """Flash (everything the board stores) and static RAM of the image's sections."""
    size = {name: sz for name, _, sz in rows}
    flash = sum(size.get(s, 0) for s in (".boot2", ".vector_table", ".text", ".rodata", ".data"))
    static_ram = sum(size.get(s, 0) for s in (".data", ".bss", ".uninit"))
    return {"flash": flash, "static_ram": static_ram}


def parse(report):
    """The cost figures of one `codegen run --target rp2040 --io pins --json` report; exits naming what is wrong."""
    board = report.get("board")
    if report.get("target") != "rp2040" or not board:
        sys.exit("pico cost: the report is not from a run on the RP2040 harness")
    problems = []
    if report["violations"] != 0:
        problems.append(f"{report['violations']} violations")
    if board["hidden_commands"] != 0 or board["missed"] != 0:
        problems.append(f"{board['hidden_commands']} hidden commands, {board['missed']} missed edges")
    figures = {}
    for name, key in (("apply", "apply"), ("decide", "decision"), ("idle_decide", "idle_decision")):
        c = board["cost"][key]
        if c["calls"] == 0:
            problems.append(f"no '{key}' measured")
        figures[f"{name}.avg"] = c["avg_instructions"]
        figures[f"{name}.cycles.avg"] = c["avg_cycles"]
        if name != "idle_decide":
            figures[f"{name}.max"] = c["max_instructions"]
            figures[f"{name}.cycles.max"] = c["max_cycles"]
    if problems:
        sys.exit("pico cost: " + "; ".join(problems))
    return figures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--target-dir", help="cargo's target directory for the build")
    args = ap.parse_args()
    target_dir = args.target_dir or os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    build(target_dir, [], "pico-build")
    elf = os.path.join(target_dir, "thumbv6m-none-eabi", "release", "cell-pico")
    rows = sections(elf)
    check_memory(elf, rows)
    cmd = ["cargo", "run", "--quiet", "--release", "-p", "codegen", "--", "run", "--target", "rp2040", "--io", "pins",
           "--events", str(EVENTS), "--json"]
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.abspath(target_dir))
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if run.returncode not in (0, 1):
        sys.stderr.write(run.stderr)
        sys.exit(f"{' '.join(cmd)} exited with {run.returncode}")
    report = json.loads(run.stdout)
    board = report["board"]
    print(f"cell on the emulated RP2040: {report['events']} events, {board['sampling']} sampling, "
          f"{board['cost']['apply']['calls']} applies, {board['cost']['decision']['calls']} decisions measured")
    figures = parse(report)
    figures.update(footprint(rows))
    expect.check(os.path.join(ROOT, ".ci", "expected", "cell-pico.cost"), figures)


if __name__ == "__main__":
    main()
