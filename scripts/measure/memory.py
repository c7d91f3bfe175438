"""How well `codegen synth` holds `--memory-limit`, and the conflict check of independent subsystems, on
copies of Wonham's AGV system (examples/agv/agv.wmod; copy k renames every event and component with the
suffix `_k`, so the copies share nothing).

- Peak resident size against the limit: `codegen synth --monolithic --memory-limit L` on three copies
  (the monolithic product is the product of the three closed loops, far past any limit here) must stop
  with the memory-limit error, its peak RSS (getrusage of the child) within 10 % of L.
- The conflict check decomposed: `codegen synth --engine explicit` on the three copies (their local
  modular sets share no event, so each copy's set is checked alone): wall time, goal under 10 s.

A benchmark, not a test: it prints the figures and exits 1 when a goal is missed.

    python3 scripts/measure/memory.py [CODEGEN] [--limits 1G,2G]
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
MODULE = os.path.join(ROOT, "examples", "agv", "agv.wmod")
NS = "http://waters.sourceforge.net/xsd/module"


def copies(n, path):
    """Writes a module of `n` renamed copies of the AGV module to `path`."""
    ET.register_namespace("", NS)
    ET.register_namespace("B", "http://waters.sourceforge.net/xsd/base")
    root = ET.parse(MODULE).getroot()
    decls = root.find(f"{{{NS}}}EventDeclList")
    comps = root.find(f"{{{NS}}}ComponentList")
    events = [d for d in decls if d.get("Name") != ":accepting"]
    originals = list(comps)
    for d in events:
        decls.remove(d)
    for c in originals:
        comps.remove(c)
    for k in range(1, n + 1):
        rename = lambda name: name if name.startswith(":") else f"{name}_{k}"
        for d in events:
            e = ET.fromstring(ET.tostring(d))
            e.set("Name", rename(e.get("Name")))
            decls.append(e)
        for c in originals:
            c = ET.fromstring(ET.tostring(c))
            c.set("Name", rename(c.get("Name")))
            for ident in c.iter(f"{{{NS}}}SimpleIdentifier"):
                ident.set("Name", rename(ident.get("Name")))
            comps.append(c)
    root.set("Name", f"agv{n}")
    ET.ElementTree(root).write(path, encoding="UTF-8", xml_declaration=True)


def size(text):
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}
    return int(text[:-1]) * units[text[-1].upper()] if text[-1].upper() in units else int(text)


def run(cmd):
    """Runs `cmd`; (exit status, stderr, wall seconds, peak RSS in bytes of the largest child so far —
    so each limit is measured in a process of its own, whose only child is that run)."""
    start = time.monotonic()
    out = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return out.returncode, out.stderr, wall, peak * 1024


def main():
    p = argparse.ArgumentParser()
    p.add_argument("codegen", nargs="?", default=os.path.join(ROOT, "target", "release", "codegen"))
    p.add_argument("--limits", default="1G,2G")
    p.add_argument("--one", help=argparse.SUPPRESS)
    args = p.parse_args()
    work = tempfile.mkdtemp(prefix="memory-")
    module = os.path.join(work, "agv3.wmod")
    copies(3, module)
    if args.one:
        # One limit, in a process of its own (so that ru_maxrss is this run's).
        limit = size(args.one)
        status, err, wall, peak = run([args.codegen, "synth", "--monolithic", "--memory-limit", args.one, module])
        ok = status == 2 and "memory limit" in err and peak <= 1.1 * limit
        print(f"memory  limit {args.one:>5}  peak RSS {peak / 2**30:.2f} GiB = {peak / limit:.2f} x limit  "
              f"({wall:.1f} s, exit {status})  {'ok' if ok else 'MISSED'}")
        if status != 2 or "memory limit" not in err:
            print(err.strip()[-400:])
        sys.exit(0 if ok else 1)
    missed = 0
    for limit in args.limits.split(","):
        missed += subprocess.run([sys.executable, __file__, args.codegen, "--one", limit]).returncode != 0
    status, err, wall, _ = run([args.codegen, "synth", "--engine", "explicit", module])
    ok = status == 0 and wall < 10
    print(f"conflict check of three independent AGV copies, explicit: {wall:.1f} s (goal < 10 s, exit {status})"
          f"  {'ok' if ok else 'MISSED'}")
    missed += not ok
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
