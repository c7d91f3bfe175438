"""The distribution station on the Cortex-M3 under QEMU, state-based (`[runtime] mode = "state"`: F_σ as
cubes over the signal word, firmware::state) against the same station event-based (its supervisor tables,
firmware::runtime): flash, static RAM, the runtime's code and tables and the instructions per decision and
per sensor event. Both images are the cell-qemu application (the footprint) and the cost-qemu harness (the
instructions, `-icount shift=7,sleep=off`) built on tables `codegen emit` writes from
examples/distribution/distribution-state.toml, once as it is and once with `mode = "event"`. Every figure
must be measured (footprint.py and cost.py fail on a missing symbol or line); the figures are compared with
`.ci/expected/distribution-state.txt`.

    python3 scripts/measure/state.py
"""

import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
import cost  # noqa: E402
import expect  # noqa: E402
import footprint  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
MANIFEST = os.path.join(ROOT, "examples", "distribution", "distribution-state.toml")
EXPECTED = os.path.join(ROOT, ".ci", "expected", "distribution-state.txt")
# The figures compared: footprint.py's and cost.py's names.
FIGURES = ("flash", "static_ram", "code", "code.apply", "code.decide", "tables", "code+tables", "runtime_ram",
           "apply.avg", "decide.avg", "decide.max", "enabled.avg", "idle_decide.avg")


def emit(manifest, out):
    """`codegen emit MANIFEST -o OUT`."""
    run = subprocess.run(["cargo", "run", "--quiet", "-p", "codegen", "--", "emit", manifest, "-o", out], cwd=ROOT,
                         capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stderr)
        sys.exit(f"state: codegen emit {manifest} exited with {run.returncode}")


def event_manifest(scratch):
    """distribution-state.toml with `mode = "event"`, its model paths made absolute."""
    text = open(MANIFEST).read()
    if 'mode = "state"' not in text:
        sys.exit(f"state: {MANIFEST} does not say mode = \"state\"")
    base = os.path.dirname(MANIFEST)
    for folder in ("plants/", "specs/"):
        text = text.replace(f'"{folder}', f'"{os.path.join(base, folder)}')
    path = os.path.join(scratch, "distribution-event.toml")
    with open(path, "w") as f:
        f.write(text.replace('mode = "state"', 'mode = "event"'))
    return path


def measure(tables, target_dir):
    """Footprint and cost of the images built on `tables`."""
    os.environ["SCT_TABLES"] = tables
    footprint.build(target_dir, [], "qemu-build")
    figures = footprint.measure(os.path.join(target_dir, "thumbv7m-none-eabi", "release", "cell-qemu"))
    out = footprint.build(target_dir, [], "qemu-cost")
    sys.stdout.write(out)
    figures.update(cost.parse(out))
    return {k: v for k, v in figures.items() if k in FIGURES}


def main():
    target_dir = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    with tempfile.TemporaryDirectory() as scratch:
        state_tables = os.path.join(scratch, "state.rs")
        event_tables = os.path.join(scratch, "event.rs")
        emit(MANIFEST, state_tables)
        emit(event_manifest(scratch), event_tables)
        if "firmware::state::StateTables" not in open(state_tables).read():
            sys.exit("state: the state tables hold no firmware::state::StateTables")
        figures = {}
        for mode, tables in (("state", state_tables), ("event", event_tables)):
            print(f"== {mode}-based")
            for name, value in measure(tables, target_dir).items():
                figures[f"{mode}.{name}"] = value
    os.environ.pop("SCT_TABLES", None)
    print(f"{'figure':<18} {'state':>8} {'event':>8}")
    for name in FIGURES:
        print(f"{name:<18} {figures.get('state.' + name, '-'):>8} {figures.get('event.' + name, '-'):>8}")
    expect.check(EXPECTED, figures)


if __name__ == "__main__":
    main()
