"""Times wmslice against manifold3d on meshes with real coordinate patterns
(run by bench/compare with the venv's Python, or by hand):

    python real.py --wmslice PATH [--wmslice-base PATH] [--layers 2000] \
        [--runs 3] [--out DIR] [--no-pin] [--snap S] [--weld] [--null] MESH...

For each mesh (STL, OBJ, OFF, PLY): the layer height H is the height span
over LAYERS rounded to four significant digits (a decimal), the planes
are wmslice's default uniform plan (lowest vertex + H/2, then every H up
to the highest vertex), given to manifold3d as their nearest doubles.

- wmslice: wall time of `wmslice slice MESH --layer-height H --threads 1
  --quiet --format json -o OUT --verbose` (read, weld, validate, slice,
  write the JSON, fsync); the number paths it reports are kept, the JSON
  is removed once timed (and compared, with --wmslice-base). With
  `--snap S`, wmslice snaps (real meshes' usual mode) and slices its
  own plan on the snapped mesh; manifold3d keeps the unsnapped plan.
  With `--weld`, wmslice merges an indexed file's vertices at one point
  (manifold3d's input is merged the same way below).
  With `--null`, also the same command with `-o /dev/null` (everything
  but the file: manifold3d writes nothing), and its ratio.
- manifold3d: `Manifold(Mesh(...))` plus `slice(z).to_polygons()` per
  level, timed inside the process (construction plus slicing; reading
  the file with trimesh is not counted). A mesh it refuses is shown
  "failed"; one it returns no loop for at every level (a mesh at the small
  end of the double range, which its tolerance takes for empty) "no
  loops". Neither enters the geometric mean.

Each process is pinned to one CPU (`--no-pin`: not): the comparison is one
thread against one thread, and manifold3d, built with TBB, would otherwise
construct on every core.

Prints a Markdown table (medians of RUNS; ratio = manifold3d / wmslice,
above 1: wmslice is faster; JSON MB: the size of the file wmslice wrote,
which the written column pays for and manifold3d does not) and the
geometric mean of the ratios.
"""

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time
from fractions import Fraction

MANIFOLD = r"""
import json, sys, time
import numpy as np
import trimesh
from manifold3d import Manifold, Mesh
path, levels_file = sys.argv[1], sys.argv[2]
levels = [float(x) for x in open(levels_file).read().split()]
m = trimesh.load_mesh(path, process=False, skip_materials=True)
# Vertices as written, exactly equal points merged (an STL's corners), as
# wmslice welds; manifold3d holds float32.
# -0 and +0 are one coordinate, as wmslice welds (+ 0.0 turns -0 to +0).
flat = np.ascontiguousarray(m.vertices, dtype=np.float64) + 0.0
keys = flat.view(np.dtype((np.void, 24))).ravel()
_, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
verts = np.ascontiguousarray(flat[first], dtype=np.float32)
faces = np.ascontiguousarray(inverse.reshape(-1)[m.faces], dtype=np.uint32)
t = time.perf_counter()
man = Manifold(Mesh(vert_properties=verts, tri_verts=faces))
status = str(man.status())
build = time.perf_counter() - t
t = time.perf_counter()
loops = 0
for z in levels:
    loops += len(man.slice(z).to_polygons())
sl = time.perf_counter() - t
print(json.dumps(dict(build_s=build, slice_s=sl, loops=loops, status=status,
                      tris=int(man.num_tri()), faces=len(faces))))
"""


def four_digits(x):
    """x rounded to four significant digits, as an exact decimal Fraction."""
    e = math.floor(math.log10(x)) - 3
    return Fraction(round(x / 10**e)) * Fraction(10) ** e


def dec(x):
    x = Fraction(x)
    sign = "-" if x < 0 else ""
    x = abs(x)
    digits = 0
    while x.denominator != 1:
        x *= 10
        digits += 1
    s = str(x.numerator).rjust(digits + 1, "0")
    if digits:
        s = s[:-digits] + "." + s[-digits:]
    return sign + s


def z_range(path):
    import trimesh

    m = trimesh.load_mesh(path, process=False, skip_materials=True)
    z = m.vertices[:, 2]
    return Fraction(float(z.min())), Fraction(float(z.max()))


def one_cpu(pin):
    """Pins this process, and so every child it starts, to one CPU (nothing
    when `pin` is false): manifold3d is built with TBB and otherwise
    constructs on every core. Not a `preexec_fn`: that makes Python fork
    its whole (numpy-sized) process for each child, 6-9 ms that would be
    charged to wmslice's wall time and not to manifold3d's in-process one."""
    if pin:
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


def wall(cmd):
    t = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True)
    s = time.perf_counter() - t
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {out.stderr.strip()[-400:]}")
    return s, out.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--wmslice", required=True)
    ap.add_argument("--wmslice-base", default="")
    ap.add_argument("--layers", type=int, default=2000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "out"))
    ap.add_argument("--no-pin", dest="pin", action="store_false",
                    help="do not pin each process to one CPU")
    ap.add_argument("--snap", default="",
                    help="run wmslice with --snap S (manifold3d's planes unchanged)")
    ap.add_argument("--weld", action="store_true",
                    help="run wmslice with --weld (vertices at one point merged, exactly)")
    ap.add_argument("--null", action="store_true",
                    help="also time wmslice writing its JSON to /dev/null")
    ap.add_argument("meshes", nargs="+")
    args = ap.parse_args()
    one_cpu(args.pin)
    os.makedirs(args.out, exist_ok=True)
    tools = [("wmslice", args.wmslice)] + ([("base", args.wmslice_base)] if args.wmslice_base else [])
    verbose = {b: "--verbose" in subprocess.run([b, "slice", "--help"], capture_output=True,
                                                 text=True).stdout for _, b in tools}
    # What wmslice is asked to do to the mesh before slicing; `check` is
    # asked the same.
    repairs = (["--snap", args.snap] if args.snap else []) + (["--weld"] if args.weld else [])
    rows = []
    for mesh in args.meshes:
        name = os.path.basename(mesh)
        check = subprocess.run([args.wmslice, "check", mesh, *repairs], capture_output=True,
                               text=True)
        if check.returncode != 0:
            why = (check.stderr.strip().splitlines() or ["no message"])[-1]
            print(f"{name}: refused by wmslice check ({why}), skipped", flush=True)
            continue
        try:
            lo, hi = z_range(mesh)
        except Exception as e:  # trimesh reads manifold3d's input: no peer to time
            print(f"{name}: trimesh cannot read it ({type(e).__name__}), skipped", flush=True)
            continue
        h = four_digits(float(hi - lo) / args.layers)
        levels = []
        z = lo + h / 2
        while z <= hi:
            levels.append(z)
            z += h
        levels_file = os.path.join(args.out, f"levels_{name}.txt")
        with open(levels_file, "w") as f:
            f.write("\n".join(repr(float(v)) for v in levels) + "\n")
        row = dict(mesh=name, layers=len(levels), h=dec(h))
        for tool, binary in tools:
            out = os.path.join(args.out, f"real_{tool}_{name}.json")
            cmd = [binary, "slice", mesh, "--layer-height", dec(h), "--threads", "1", "--quiet",
                   "--format", "json", "-o", out]
            if verbose[binary]:
                cmd.append("--verbose")
            cmd += repairs
            times = []
            err = ""
            try:
                for _ in range(args.runs):
                    if os.path.exists(out):
                        os.remove(out)
                    os.sync()
                    s, err = wall(cmd)
                    times.append(s)
                    if s > 20:
                        break
            except RuntimeError as e:
                row[tool + "_error"] = str(e)[-300:]
                times = []
            row[tool] = statistics.median(times) if times else None
            if tool == "wmslice" and times:
                # What "written" writes: the cost of the file beside the
                # /dev/null column (manifold3d writes nothing).
                row["json_bytes"] = os.path.getsize(out)
            m = re.search(r"number paths \(loop points\): (.*)", err)
            if m:
                row["paths"] = m.group(1).strip()
            if args.null and tool == "wmslice" and times:
                null_cmd = cmd[:cmd.index("-o") + 1] + ["/dev/null"] + cmd[cmd.index("-o") + 2:]
                row["null"] = statistics.median(wall(null_cmd)[0] for _ in range(args.runs))
        if len(tools) == 2 and row["wmslice"] and row["base"]:
            same = open(os.path.join(args.out, f"real_wmslice_{name}.json"), "rb").read() == \
                open(os.path.join(args.out, f"real_base_{name}.json"), "rb").read()
            row["identical"] = same
        # Each output is removed once timed and compared (2 000 layers of
        # a large part are hundreds of MB; 138 parts filled 14 GB).
        for tool, _ in tools:
            out = os.path.join(args.out, f"real_{tool}_{name}.json")
            if os.path.exists(out):
                os.remove(out)
        peer = []
        for _ in range(args.runs):
            r = subprocess.run([sys.executable, "-c", MANIFOLD, mesh, levels_file],
                               capture_output=True, text=True)
            if r.returncode != 0:
                peer = None
                row["manifold_error"] = r.stderr.strip()[-300:]
                break
            peer.append(json.loads(r.stdout.strip().splitlines()[-1]))
        if peer and peer[0]["tris"] != peer[0]["faces"]:
            row["manifold_error"] = f"{peer[0]['status']}: {peer[0]['tris']} of {peer[0]['faces']} faces"
            peer = None
        if peer and peer[0]["loops"] == 0:
            # Every level lies strictly inside the mesh's z range: no loop
            # at all is no answer (manifold3d's tolerance took a mesh at
            # the small end of the double range for empty), not a time.
            row["manifold_error"] = f"no loop at any of the {len(levels)} levels"
            row["manifold_empty"] = True
            peer = None
        if peer:
            row["manifold"] = statistics.median(p["build_s"] + p["slice_s"] for p in peer)
            row["manifold_loops"] = peer[0]["loops"]
        rows.append(row)
        print(json.dumps(row), flush=True)

    head = "| mesh | layers | H | wmslice s |" + (" before s |" if len(tools) == 2 else "") + \
        " manifold3d s | ratio |" + (" to /dev/null s | ratio |" if args.null else "") + \
        " JSON MB | number paths |"
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    ratios = []
    null_ratios = []
    for r in rows:
        ratio = r["manifold"] / r["wmslice"] if r.get("manifold") and r["wmslice"] else None
        if ratio:
            ratios.append(ratio)
        null_ratio = r["manifold"] / r["null"] if r.get("manifold") and r.get("null") else None
        if null_ratio:
            null_ratios.append(null_ratio)
        show = lambda v: f"{v:.3f}" if v else "failed"
        cells = [r["mesh"], str(r["layers"]), r["h"], show(r["wmslice"])]
        if len(tools) == 2:
            cells.append(show(r["base"]) + ("" if r.get("identical", True) else " (OUTPUT DIFFERS)"))
        peer_cell = "no loops" if r.get("manifold_empty") else "failed"
        cells += [f"{r['manifold']:.3f}" if r.get("manifold") else peer_cell,
                  f"{ratio:.2f}" if ratio else "-"]
        if args.null:
            cells += [show(r.get("null")), f"{null_ratio:.2f}" if null_ratio else "-"]
        cells.append(f"{r['json_bytes'] / 1e6:.1f}" if r.get("json_bytes") else "-")
        cells.append(r.get("paths", ""))
        lines.append("| " + " | ".join(cells) + " |")
    for label, rs in [("", ratios), (" (JSON to /dev/null)", null_ratios)]:
        if rs:
            g = math.exp(sum(math.log(x) for x in rs) / len(rs))
            lines.append("")
            lines.append(f"Geometric mean of the ratios{label}: {g:.2f} "
                         f"(min {min(rs):.2f}, max {max(rs):.2f})")
    text = "\n".join(lines)
    print("\n" + text)
    open(os.path.join(args.out, "real.md"), "w").write(text + "\n")


if __name__ == "__main__":
    main()
