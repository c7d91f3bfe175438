#!/usr/bin/env python3
"""Times `codegen synth` against libFAUDES and TCT on the same generated instances, in the same run.

usage: timing.py SYNTH_TIME FAMILIES WORKDIR [TIMEOUT_SECONDS]

For each family and size it writes the instance (the `families` example), then times, each in a fresh
process with a timeout and counting the synthesis calls only (not reading files or building models): our
release build (the `synth_time` example, best of three), libFAUDES and TCT (one run each). Monolithic families time
supC of the whole plant and specification; `cat-mouse` times the local modular supervisors plus the
conflict check. Prints a Markdown table with the ratio of the faster reference tool to ours.
"""
import os
import subprocess
import sys
import time

PLAN = [
    ("factory", [4, 5, 6, 7], "monolithic"),
    ("transfer-line", [8, 10, 12, 14], "monolithic"),
    ("philosophers", [5, 6, 7, 8], "monolithic"),
    ("random", [4, 5, 6], "monolithic"),
    ("cat-mouse", [2, 3, 4], "conflict"),
]


def child(tool, mode, manifest, work):
    """Runs one reference tool on one instance and prints (seconds, states)."""
    import tools

    plants, specs = tools.read_manifest(manifest)
    if tool == "faudes":
        import faudes

        if mode == "monolithic":
            g = tools.faudes_product(plants)  # models are built from files before the clock starts
            start = time.perf_counter()
            sup = tools.faudes_supc(plants, specs)
            states = sup.Size()
        else:
            start = time.perf_counter()
            sups = []
            for e in specs:
                local = [p for p in plants if set(p.events) & set(e.events)]
                sups.append(tools.faudes_supc(local, [e]))
            vec = faudes.GeneratorVector()
            for s in sups:
                vec.Append(s)
            faudes.IsNonblocking(vec)
            states = sum(s.Size() for s in sups)
    else:
        import pitct

        t = tools.Tct(work, plants + specs)
        if mode == "monolithic":
            start = time.perf_counter()
            t.supc("SUP", plants, specs)
            states = pitct.statenum("SUP")
        else:
            start = time.perf_counter()
            names = []
            for i, e in enumerate(specs):
                local = [p for p in plants if set(p.events) & set(e.events)]
                names.append(t.supc(f"S{i}", local, [e]))
            universe = {ev for a in plants + specs for ev in a.events}
            lifted = []
            for i, n in enumerate(names):
                extra = sorted(t.code[ev] for ev in universe - set(pitct.events(n, convert=False)))
                pitct.selfloop(f"L{i}", n, extra) if extra else pitct.meet(f"L{i}", n, n)
                lifted.append(f"L{i}")
            pitct.meet("REST", *lifted[:-1]) if len(lifted) > 2 else pitct.meet("REST", lifted[0], lifted[0])
            pitct.nonconflict("REST", lifted[-1])
            states = sum(pitct.statenum(n) for n in names)
    print(f"{time.perf_counter() - start:.4f} {states}")


def timed(cmd, timeout):
    start = time.perf_counter()
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, None
    if out.returncode not in (0, 1):
        return None, None
    return time.perf_counter() - start, out.stdout


def main():
    synth_time, families, work = sys.argv[1:4]
    timeout = float(sys.argv[4]) if len(sys.argv) > 4 else 25.0
    here = os.path.dirname(os.path.abspath(__file__))
    py = sys.executable
    print("| family | n | architecture | supervisor states | codegen (s) | libFAUDES (s) | TCT (s) | speed-up vs faster |")
    print("|---|---|---|---|---|---|---|---|")
    for family, sizes, mode in PLAN:
        for n in sizes:
            d = os.path.join(work, f"{family}-{n}")
            manifest = subprocess.run([families, family, str(n), d], check=True, capture_output=True, text=True).stdout.strip()
            _, out = timed([synth_time, mode, manifest], 3 * timeout)
            ours, states = (float(out.split()[0]), out.split()[1]) if out else (None, "-")
            refs = {}
            for tool in ("faudes", "tct"):
                _, out = timed([py, os.path.join(here, "timing.py"), "--child", tool, mode, manifest, os.path.join(d, tool)], timeout)
                refs[tool] = float(out.strip().splitlines()[-1].split()[0]) if out else None
            fmt = lambda t: f"{t:.3f}" if t is not None else f"> {timeout:.0f}"
            known = [t for t in refs.values() if t is not None]
            if ours is None:
                ratio = "-"
            elif known:
                ratio = f"{min(known) / ours:.1f}x"
            else:
                ratio = f"> {timeout / ours:.0f}x"
            print(f"| {family} | {n} | {mode} | {states} | {fmt(ours)} | {fmt(refs['faudes'])} | {fmt(refs['tct'])} | {ratio} |", flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "--child":
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        child(*sys.argv[2:6])
    else:
        main()
