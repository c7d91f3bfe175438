"""Footprint of the cell firmware (cell-qemu, release): flash and RAM from llvm-size, and the runtime's share
from the symbol table — code of the runtime library (firmware::{runtime,choice,rng,table,event_set,
input_queue}) and the emitted tables the runtime reads. The runtime's entry points are out of line
(`#[inline(never)]`), so their code carries their own names; interface code (UART, link protocol, RTIC glue,
logs) is counted apart.

Symbol names are read in both manglings rustc uses (legacy `firmware::runtime::Runtime$LT$…$GT$::apply::h…`
and v0 `<firmware::runtime::Runtime<…>>::apply`); an expected symbol that is not found fails the run, as does
an image linked for the wrong memory. The figures are compared with `.ci/expected/cell-qemu.size`.

    python3 scripts/measure/footprint.py                 # the committed cell tables, checked
    SCT_TABLES=other.rs python3 scripts/measure/footprint.py --no-expected
    python3 scripts/measure/footprint.py --elf FILE      # an ELF built elsewhere (no build)
    python3 scripts/measure/footprint.py --target-dir target/v0 \
        --cargo-config 'target.thumbv7m-none-eabi.rustflags=["-Csymbol-mangling-version=v0"]'
"""

import argparse
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))
import expect  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
RUNTIME_MODULES = ("runtime", "shell", "choice", "rng", "table", "event_set", "input_queue", "state")
# Supervisor tables (the image's sections and the set over them, firmware::table::image), then the state
# tables of `[runtime] mode = "state"` (firmware::state).
TABLES = ("SECTIONS", "SET", "RULES", "CUBES", "WRITES", "HOLDERS", "COMPONENT_ENDS", "READINGS", "PLANT_EVENTS",
          "CHOICE_SITES", "TABLES")
# Tables every layout has; state tables have their own.
REQUIRED_TABLES = ("SECTIONS", "SET")
REQUIRED_STATE_TABLES = ("RULES", "CUBES", "WRITES", "READINGS", "TABLES")
NAMES = ("EVENT_NAMES", "AUTOMATON_NAMES", "SIGNAL_NAMES")
# Entry points the runtime keeps out of line; each must be found, or the code figure means nothing.
ENTRY_POINTS = ("apply", "decide")
# lm3s6965evb: flash at 0, 256 KiB; SRAM at 0x2000_0000, 64 KiB.
FLASH = (0x0, 256 * 1024)
RAM = (0x2000_0000, 64 * 1024)


def tool(name):
    sysroot = subprocess.run(["rustc", "--print", "sysroot"], capture_output=True, text=True, check=True).stdout.strip()
    host = re.search(r"^host: (\S+)$", subprocess.run(["rustc", "-vV"], capture_output=True, text=True, check=True).stdout, re.M).group(1)
    path = os.path.join(sysroot, "lib", "rustlib", host, "bin", name)
    if not os.path.exists(path):
        sys.exit(f"footprint: {path} not found (rustup component add llvm-tools; scripts/setup.sh does)")
    return path


def plain(symbol):
    """A demangled symbol with the legacy mangling's decorations removed (`$LT$`/`$GT$` escapes, the
    trailing `::h<hash>`), so both manglings read `<firmware::runtime::Runtime<…>>::apply`."""
    s = symbol.replace("$LT$", "<").replace("$GT$", ">").replace("$C$", ",").replace("$u20$", " ")
    if "$" in symbol or re.search(r"::h[0-9a-f]{16}$", symbol):
        # Legacy paths inside escapes use `..` for `::`, and a name cannot start with `<`: `_<…>`.
        s = s.replace("..", "::")
        if s.startswith("_<"):
            s = s[1:]
    return re.sub(r"::h[0-9a-f]{16}$", "", s)


def path_of(s):
    """The path a symbol starts with (`firmware::runtime::…`), past the `<` of a qualified `<T>::f` or
    `<T as Trait>::f`."""
    return s.lstrip("<")


def last_segment(s):
    """The item's own name: the last path segment outside any generic brackets (a turbofish `::<…>` is
    the generic arguments of the segment before it, not a segment)."""
    depth, start, i = 0, 0, 0
    while i < len(s):
        if s[i] == "<":
            depth += 1
        elif s[i] == ">":
            depth -= 1
        elif depth == 0 and s.startswith("::", i) and not s.startswith("::<", i):
            start = i + 2
            i += 1
        i += 1
    return s[start:].split("<", 1)[0].split("::", 1)[0]


def classify(symbols):
    """Groups (size, type, name) symbols into the footprint's kinds; returns {kind: [(size, name)]}."""
    kinds = {k: [] for k in ("code", "tables", "names", "runtime RAM", "input buffer RAM")}
    for size, typ, name in symbols:
        p = plain(name)
        if typ in "tT" and re.match(r"firmware::(%s)::" % "|".join(RUNTIME_MODULES), path_of(p)):
            kinds["code"].append((size, p))
        elif typ in "rR" and re.search(r"::tables::(%s)$" % "|".join(TABLES), p):
            kinds["tables"].append((size, p))
        elif typ in "rR" and re.search(r"::tables::(%s)$" % "|".join(NAMES), p):
            kinds["names"].append((size, p))
        elif typ in "bBdD" and "local_resource_runtime" in p:
            kinds["runtime RAM"].append((size, p))
        elif typ in "bBdD" and "queue" in p:
            kinds["input buffer RAM"].append((size, p))
    return kinds


def nm(elf):
    out = subprocess.run([tool("llvm-nm"), "--print-size", "--size-sort", "--radix=d", "-C", elf],
                         capture_output=True, text=True, check=True).stdout
    symbols = []
    for line in out.splitlines():
        fields = line.split(None, 3)
        if len(fields) == 4:
            symbols.append((int(fields[1]), fields[2], fields[3]))
    return symbols


def sections(elf):
    """(name, address, size) of every allocated section."""
    out = subprocess.run([tool("llvm-size"), "-A", elf], capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        fields = line.split()
        if len(fields) == 3 and fields[1].isdigit() and fields[2].isdigit():
            rows.append((fields[0], int(fields[2]), int(fields[1])))
    return rows


def check_memory(elf, rows):
    """Fails when the vector table is not at the start of flash or a section lies outside flash and RAM:
    an image linked for another chip would otherwise be measured as if it were this one."""
    def inside(addr, size, region):
        return region[0] <= addr and addr + size <= region[0] + region[1]

    vectors = [r for r in rows if r[0] == ".vector_table"]
    if not vectors or vectors[0][1] != FLASH[0]:
        sys.exit(f"footprint: {elf}: .vector_table is not at {FLASH[0]:#x}: linked for another memory map")
    for name, addr, size in rows:
        if size and addr and not (inside(addr, size, FLASH) or inside(addr, size, RAM)):
            sys.exit(f"footprint: {elf}: section {name} at {addr:#x} is outside lm3s6965evb flash and RAM")


def measure(elf):
    rows = sections(elf)
    check_memory(elf, rows)
    size = {name: sz for name, _, sz in rows}
    flash = sum(sz for name, addr, sz in rows if name in (".vector_table", ".text", ".rodata", ".data"))
    static_ram = sum(sz for name, _, sz in rows if name in (".data", ".bss", ".uninit"))
    kinds = classify(nm(elf))
    missing = []
    code_names = [last_segment(n) for _, n in kinds["code"]]
    for entry in ENTRY_POINTS:
        if entry not in code_names:
            missing.append(f"runtime entry point '{entry}'")
    table_names = [last_segment(n) for _, n in kinds["tables"]]
    for table in REQUIRED_STATE_TABLES if "TABLES" in table_names else REQUIRED_TABLES:
        if table not in table_names:
            missing.append(f"table '{table}'")
    if not kinds["runtime RAM"]:
        missing.append("the runtime's RAM (local_resource_runtime)")
    if missing:
        sys.exit(f"footprint: {elf}: not found in the symbol table: {', '.join(missing)}")

    for kind, items in kinds.items():
        print(f"{kind}: {sum(s for s, _ in items)} bytes")
        for s, n in sorted(items):
            print(f"    {s:5d}  {n}")
    total = lambda k: sum(s for s, _ in kinds[k])  # noqa: E731
    figures = {
        "flash": flash,
        "static_ram": static_ram,
        "code": total("code"),
        "tables": total("tables"),
        "code+tables": total("code") + total("tables"),
        "names": total("names"),
        "runtime_ram": total("runtime RAM"),
        "input_buffer_ram": total("input buffer RAM"),
    }
    for s, n in kinds["code"]:
        if last_segment(n) in ENTRY_POINTS:
            figures[f"code.{last_segment(n)}"] = s
    for s, n in kinds["tables"]:
        figures[f"table.{last_segment(n)}"] = s
    print(f"flash {flash} B (.text {size.get('.text', 0)}, .rodata {size.get('.rodata', 0)}), static RAM {static_ram} B")
    print(f"runtime code + tables: {figures['code+tables']} bytes")
    return figures


def build(target_dir, configs, alias):
    """Runs the cargo alias `alias` (from the root's .cargo/config.toml) into `target_dir` with extra
    `--config` values; returns its stdout."""
    cmd = ["cargo"] + [a for c in configs for a in ("--config", c)] + [alias, "--quiet"]
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.abspath(target_dir))
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(f"{' '.join(cmd)} exited with {run.returncode}")
    return run.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--elf", help="measure this ELF instead of building cell-qemu")
    ap.add_argument("--expected", default=os.path.join(ROOT, ".ci", "expected", "cell-qemu.size"))
    ap.add_argument("--no-expected", action="store_true", help="print only (other tables than the cell's)")
    ap.add_argument("--target-dir", help="cargo's target directory for the build")
    ap.add_argument("--cargo-config", action="append", default=[], help="a `--config` for the build")
    args = ap.parse_args()
    elf = args.elf
    if elf is None:
        target_dir = args.target_dir or os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
        build(target_dir, args.cargo_config, "qemu-build")
        elf = os.path.join(target_dir, "thumbv7m-none-eabi", "release", "cell-qemu")
    figures = measure(elf)
    if not args.no_expected:
        if os.environ.get("SCT_TABLES") and args.elf is None:
            sys.exit("footprint: SCT_TABLES selects other tables than the expectations are for; add --no-expected")
        expect.check(args.expected, figures)


if __name__ == "__main__":
    main()
