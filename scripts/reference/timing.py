#!/usr/bin/env python3
"""Times `codegen synth` against libFAUDES and TCT on the same generated instances, in the same run.

usage: timing.py SYNTH_TIME FAMILIES WORKDIR [TIMEOUT_SECONDS]
       timing.py --engines CODEGEN FAMILIES WORKDIR [TIMEOUT_SECONDS]

For each family and size it writes the instance (the `families` example), then times, each in a fresh
process with a timeout and counting the synthesis calls only (not reading files or building models): our
release build (the `synth_time` example, best of three), libFAUDES and TCT (one run each). Monolithic families time
supC of the whole plant and specification; `cat-mouse` times the local modular supervisors plus the
conflict check. Prints a Markdown table with the ratio of the faster reference tool to ours.

With --engines (issue 27): the engines side by side on the instances that outgrow explicit states (the
capacity-3 transfer line, the small factory, the philosophers, cat and mouse), each a whole process —
`codegen synth --engine explicit|symbolic|auto` (the release binary CODEGEN, `--memory-limit 2G`),
libFAUDES and TCT (a Python process reading the files, then synthesising) — with its wall time and peak
resident size (the kernel's, from wait4). A tool that timed out or stopped at a limit on one size is not
run on the larger ones of its family. Prints a Markdown table.
"""
import json
import os
import subprocess
import sys
import tempfile
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


ENGINES_PLAN = [
    ("transfer-line-k3", [6, 8, 10, 20, 30], "monolithic"),
    ("factory", [6, 8, 10, 15, 20], "monolithic"),
    ("philosophers", [8, 10, 12, 16, 20, 30, 50], "monolithic"),
    ("cat-mouse", [2, 3, 4, 5], "conflict"),
]


def measured(cmd, timeout):
    """Runs `cmd` as a whole process: (seconds, peak resident MiB, stdout), stdout None when it exited
    with 2 or more (a limit, an error), or (None, None, None) when it ran past `timeout`."""
    start = time.perf_counter()
    with tempfile.TemporaryFile() as out:
        p = subprocess.Popen(cmd, stdout=out, stderr=subprocess.DEVNULL)
        while True:
            pid, status, usage = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - start > timeout:
                p.kill()
                os.wait4(p.pid, 0)
                p.returncode = -9
                return None, None, None
            time.sleep(0.01)
        seconds = time.perf_counter() - start
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        text = out.read().decode()
    return seconds, usage.ru_maxrss / 1024, text if p.returncode in (0, 1) else None


def engines(codegen, families, work, timeout):
    """The --engines table."""
    here = os.path.dirname(os.path.abspath(__file__))
    py = sys.executable
    tools_ = ["explicit", "symbolic", "auto", "faudes", "tct"]
    print(f"Whole process, wall seconds / peak MiB; codegen {2 * timeout:.0f} s, libFAUDES and TCT {timeout:.0f} s timeouts.")
    print()
    print("| instance | mode | supervisor states | explicit | symbolic | auto (ran) | libFAUDES | TCT |")
    print("|---|---|---|---|---|---|---|---|")
    for family, sizes, mode in ENGINES_PLAN:
        given_up = {}
        for n in sizes:
            d = os.path.join(work, f"{family}-{n}")
            manifest = subprocess.run([families, family, str(n), d], check=True, capture_output=True, text=True).stdout.strip()
            cells, states = {}, "-"
            for tool in tools_:
                if tool in given_up:
                    cells[tool] = f"not run ({given_up[tool]} at a smaller n)"
                    continue
                if tool in ("faudes", "tct"):
                    cmd = [py, os.path.join(here, "timing.py"), "--child", tool, mode, manifest, os.path.join(d, tool)]
                    limit = timeout
                else:
                    cmd = [codegen, "synth", "--engine", tool, "--json", "--memory-limit", "2G",
                           "--monolithic" if mode == "monolithic" else "--no-merge", manifest]
                    limit = 2 * timeout
                seconds, mib, out = measured(cmd, limit)
                if seconds is None:
                    given_up[tool] = "timed out"
                    cells[tool] = f"> {limit:.0f} s"
                elif out is None:
                    given_up[tool] = "stopped"
                    cells[tool] = f"stopped at a limit ({seconds:.1f} s / {mib:.0f} MiB)"
                else:
                    cells[tool] = f"{seconds:.2f} / {mib:.0f}"
                    if tool not in ("faudes", "tct"):
                        j = json.loads(out)
                        states = j["total_states"]
                        if tool == "auto":
                            cells[tool] += f" ({j.get('engine', '?')})"
            print(f"| {family}-{n} | {mode} | {states} | " + " | ".join(cells[t] for t in tools_) + " |", flush=True)


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
    elif sys.argv[1] == "--engines":
        engines(*sys.argv[2:5], float(sys.argv[5]) if len(sys.argv) > 5 else 60.0)
    else:
        main()
