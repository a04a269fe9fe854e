"""The timing half of bench/compare (run by it, with the venv's Python).

For every mesh and layer count: the same exact layer plan for every tool
(wmslice gets it as decimals, the peers as the nearest doubles), each tool
run RUNS times as a separate process, medians reported. Prints the machine,
the commands and a Markdown table with ratios (peer / wmslice) per row, and
writes them to OUT/results.md and OUT/results.json.
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from fractions import Fraction

HERE = os.path.dirname(os.path.abspath(__file__))


def dec(x):
    """Exact decimal text of a Fraction whose denominator is 2^a 5^b."""
    x = Fraction(x)
    sign = "-" if x < 0 else ""
    x = abs(x)
    digits = 0
    while x.denominator != 1:
        x *= 10
        digits += 1
        if digits > 40:
            raise ValueError("not a finite decimal")
    s = str(x.numerator).rjust(digits + 1, "0")
    if digits:
        s = s[:-digits] + "." + s[-digits:]
    return sign + s


def plan(meta, layers):
    """(first, height, count) as Fractions: exactly `layers` levels."""
    if meta["name"].startswith(("steps_", "steps64_")):
        # Flats at k * 1.25 up to 123.75, the top at 125.5: levels k * H for
        # k = 1..N hit every flat (every tenth level at 1000 layers).
        h = Fraction(125, layers)
        return h, h, layers
    lo, hi = Fraction(meta["zmin"]), Fraction(meta["zmax"])
    h = Fraction(int((hi - lo) / layers * 10000), 10000)
    first = Fraction(-int(-lo * 1000), 1000) + h / 2
    assert first + (layers - 1) * h < hi
    return first, h, layers


def machine_line():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 2**20:.0f} GiB RAM"
                break
    except OSError:
        pass
    return f"{model}, nproc {os.cpu_count()}{mem}, {platform.system()} {platform.release()}"


def load_average():
    try:
        return " ".join(open("/proc/loadavg").read().split()[:3])
    except OSError:
        return "?"


def versions():
    v = {}
    try:
        out = subprocess.run(["rustc", "--version"], capture_output=True, text=True).stdout
        v["rustc"] = out.split()[1]
    except OSError:
        pass
    for mod in ("manifold3d", "trimesh", "numpy"):
        try:
            from importlib.metadata import version

            v[mod] = version(mod)
        except Exception:
            pass
    try:
        for line in open("/usr/include/CGAL/version.h"):
            if line.startswith("#define CGAL_VERSION "):
                v["CGAL"] = line.split()[2]
    except OSError:
        pass
    return v


class Timeout(Exception):
    pass


TIMEOUT = [None]
# CPUs each timed process may run on (None: no pinning). A tool run "with
# one thread" is pinned to one CPU: manifold3d is built with TBB and, left
# alone, constructs a manifold on every core (about 1.8 cores here).
PIN = [None]


def run(cmd, cpus=1):
    """Runs `cmd` restricted to the first `cpus` CPUs this process may use.
    The child inherits this process's affinity, set just around the spawn:
    a `preexec_fn` would make Python fork its whole process for each child
    (6-9 ms here), charged to the tool's wall time."""
    saved = os.sched_getaffinity(0)
    if PIN[0]:
        os.sched_setaffinity(0, sorted(saved)[:cpus])
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT[0])
    except subprocess.TimeoutExpired:
        raise Timeout()
    finally:
        os.sched_setaffinity(0, saved)


def run_json(cmd, cpus=1):
    out = run(cmd, cpus)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def wall(cmd, cpus=1):
    t = time.perf_counter()
    out = run(cmd, cpus)
    s = time.perf_counter() - t
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({out.returncode}): {out.stderr.strip()[-500:]}")
    return s


def median_runs(fn, runs, cap):
    """Medians of each field over `runs` calls; one run only past `cap` s."""
    results = []
    for _ in range(runs):
        r = fn()
        results.append(r)
        if r["e2e_s"] > cap:
            break
    keys = results[0].keys()
    med = {k: statistics.median(r[k] for r in results) for k in keys}
    med["runs"] = len(results)
    return med


def fmt_s(x):
    return f"{x:.3f}" if x < 10 else f"{x:.2f}" if x < 100 else f"{x:.1f}"


def tool_runner(tool, args, mesh, plan_args, levels_file, cli):
    if tool.startswith("wmslice"):
        threads = "2" if tool == "wmslice-2t" else "1"

        def once():
            r = run_json([args.bench_slice, mesh, *plan_args, "--threads", threads], int(threads))
            # Not timed: removing the previous run's output (freeing a large
            # file is the file system's work, not this run's) and flushing
            # earlier writes, so that this run's fsync waits for its own data.
            out = cli[cli.index("-o") + 1]
            if os.path.exists(out):
                os.remove(out)
            os.sync()
            e2e = wall(cli, int(threads))
            return dict(load_s=r["load_s"] + r["build_s"], slice_s=r["slice_s"], e2e_s=e2e,
                        contours=r["contours"])
    elif tool.startswith("cgal"):
        def once():
            r = run_json([args.cgal, tool.split("-")[1], mesh, levels_file])
            load = r["load_s"] + r["build_s"]
            return dict(load_s=load, slice_s=r["slice_s"], e2e_s=load + r["slice_s"],
                        contours=r["polylines"])
    else:
        def once():
            r = run_json([sys.executable, os.path.join(HERE, "peers.py"), tool, mesh, levels_file])
            load = r["load_s"] + r["build_s"]
            return dict(load_s=load, slice_s=r["slice_s"], e2e_s=load + r["slice_s"],
                        contours=r["contours"])
    return once


def table(rows, machine, vers, args):
    t = args.timeout

    def cell(r, key):
        if r["status"] in ("timeout", "skipped"):
            star = "*" if r["status"] == "skipped" else ""
            return "-" if key == "load_s" else f"> {t:.0f}{star}"
        if r["status"] != "ok":
            return r["status"]
        return fmt_s(r[key])

    def ratio(r, key):
        if r["tool"] == "wmslice":
            return "1" if r["status"] == "ok" else "-"
        base = r["base"]
        if r["status"] != "ok" or base is None or base["status"] == "failed":
            return "-"
        if base["status"] in ("timeout", "skipped"):
            return f"< {r[key] / t:.3g}"
        return f"{r[key] / base[key]:.3g}"

    lines = [
        f"Machine: {machine}",
        "",
        "Versions: " + ", ".join(f"{k} {v}" for k, v in vers.items()),
        "",
        f"Command: `{args.command}` (median of {args.runs} runs per row, one thread each but"
        " wmslice-2t (`--threads 2`); "
        + ("every process pinned to as many CPUs as threads (`sched_setaffinity`)"
           if args.pin else "processes not pinned: manifold3d's TBB may use every core") + ";"
        f" a tool whose first run took over {args.cap:.0f} s was run once; timeout {t:.0f} s per run)",
        "",
        "| mesh | triangles | layers | tool | load+build s | slice s | end-to-end s | slice ratio | end-to-end ratio | curves |",
        "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        curves = str(int(r["contours"])) if r["status"] == "ok" else ""
        lines.append(
            f"| {r['mesh']} | {r['triangles']} | {r['layers']} | {r['tool']} | {cell(r, 'load_s')} | "
            f"{cell(r, 'slice_s')} | {cell(r, 'e2e_s')} | {ratio(r, 'slice_s')} | "
            f"{ratio(r, 'e2e_s')} | {curves} |"
        )
    lines += [
        "",
        "Ratios: tool time / wmslice (one thread) time, from the same run (above 1: wmslice is faster).",
        "wmslice end-to-end: wall time of `wmslice slice MESH --layer-height H --first Z0 --last Z1",
        "--threads 1 --quiet --format json -o out.json` (read the binary STL, weld, validate, build",
        "the topology, slice, write JSON, fsync, rename; the previous output is removed and earlier",
        "writes flushed before each timed run). wmslice slice: `layers::slice_levels` alone",
        "(`examples/bench_slice.rs`, which also gives load+build). Peers: load, build and slice",
        "timed inside their process (interpreter start and imports not counted, nothing written).",
        "`> T`: the run was stopped at the timeout T; `> T*`: not run, the same tool took over T",
        "on this shape with no more triangles and no more layers. Curves: closed curves (wmslice: S_O",
        "contours; CGAL: polylines; manifold3d: polygons; trimesh: discrete paths), summed over levels.",
    ]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--meshes", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--wmslice", required=True)
    ap.add_argument("--bench-slice", required=True)
    ap.add_argument("--cgal", default="")
    ap.add_argument("--sizes", nargs="+", required=True)
    ap.add_argument("--layers", nargs="+", type=int, required=True)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--cap", type=float, default=20.0,
                    help="a tool whose first run takes longer is run once")
    ap.add_argument("--timeout", type=float, default=150.0, help="seconds per process")
    ap.add_argument("--tools", default="wmslice,wmslice-2t,manifold3d,cgal-epick,cgal-epeck,trimesh")
    ap.add_argument("--command", default="bench/compare")
    ap.add_argument("--no-pin", dest="pin", action="store_false",
                    help="do not pin each process to one CPU (two for wmslice-2t)")
    ap.add_argument("--shapes", nargs="+",
                    default=["torus", "steps", "torus0", "torus0@1e-9", "knot", "steps64", "plate64"],
                    help="torus, steps: on one small grid; torus0 (origin-centred f32 with noise "
                    "near zero), knot (decimal OBJ), steps64 (f64 CAD-like), plate64 (decimal OBJ, walls "
                    "parallel to the axes: a perforated plate): real patterns; "
                    "SHAPE@Q: SHAPE with wmslice snapping to the grid Q (`--snap Q`; the peers "
                    "slice the file as read)")
    args = ap.parse_args()
    TIMEOUT[0] = args.timeout
    PIN[0] = args.pin
    os.makedirs(args.out, exist_ok=True)
    tools = args.tools.split(",")
    if not args.cgal:
        tools = [t for t in tools if not t.startswith("cgal")]

    machine = machine_line()
    vers = versions()
    load_before = load_average()
    print(f"machine: {machine}", flush=True)
    print("versions: " + ", ".join(f"{k} {v}" for k, v in vers.items()), flush=True)

    rows = []
    timed_out = []  # (tool, shape, triangles, layers)
    for size in args.sizes:
        for shape in args.shapes:
            shape, _, grid = shape.partition("@")
            snap_args = ["--snap", grid] if grid else []
            name = f"{shape}_{size}"
            meta = json.load(open(os.path.join(args.meshes, name + ".json")))
            mesh = os.path.join(args.meshes, meta.get("file", name + ".stl"))
            if grid:
                name += f" --snap {grid}"
                shape += f"@{grid}"

            for layers in args.layers:
                first, h, n = plan(meta, layers)
                last = first + (n - 1) * h
                levels_file = os.path.join(args.out, f"levels_{name.split()[0]}_{n}.txt")
                with open(levels_file, "w") as f:
                    for k in range(n):
                        f.write(repr(float(first + k * h)) + "\n")
                plan_args = ["--layer-height", dec(h), "--first", dec(first), "--last", dec(last),
                             *snap_args]
                out_json = os.path.join(args.out, f"wmslice_{name.split()[0]}_{n}.json")
                def cli_for(tool):
                    threads = "2" if tool == "wmslice-2t" else "1"
                    return [args.wmslice, "slice", mesh, *plan_args, "--threads", threads,
                            "--quiet", "--format", "json", "-o", out_json]
                print(f"\n{name} ({meta['triangles']} triangles), {n} layers: {' '.join(plan_args)}",
                      flush=True)
                base = None
                for tool in tools:
                    row = dict(mesh=name, triangles=meta["triangles"], layers=n, tool=tool,
                               command=" ".join(cli_for(tool)) if tool.startswith("wmslice") else "",
                               base=None)
                    if any(t == tool and sh == shape and tr <= meta["triangles"] and ly <= n
                           for t, sh, tr, ly in timed_out):
                        row.update(status="skipped", runs=0)
                        print(f"  {tool:11s} skipped (timed out on a smaller {shape} run)", flush=True)
                    else:
                        once = tool_runner(tool, args, mesh, plan_args, levels_file, cli_for(tool))
                        try:
                            row.update(median_runs(once, args.runs, args.cap), status="ok")
                            print(f"  {tool:11s} load+build {fmt_s(row['load_s'])} s, slice "
                                  f"{fmt_s(row['slice_s'])} s, end-to-end {fmt_s(row['e2e_s'])} s, "
                                  f"{int(row['contours'])} curves ({row['runs']} runs)", flush=True)
                        except Timeout:
                            timed_out.append((tool, shape, meta["triangles"], n))
                            row.update(status="timeout", runs=1)
                            print(f"  {tool:11s} timed out after {args.timeout:.0f} s", flush=True)
                        except RuntimeError as e:
                            row.update(status="failed", runs=1)
                            print(f"  {tool:11s} FAILED: {e}", flush=True)
                    if tool == "wmslice":
                        base = row
                    else:
                        row["base"] = base
                    rows.append(row)

    machine += f"; load average {load_before} at the start, {load_average()} at the end"
    text = table(rows, machine, vers, args)
    print("\n" + text)
    open(os.path.join(args.out, "results.md"), "w").write(text + "\n")
    for r in rows:
        r.pop("base", None)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(dict(machine=machine, versions=vers, command=args.command, rows=rows), f, indent=1)


if __name__ == "__main__":
    main()
