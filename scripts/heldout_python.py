"""The Python package against the command line on meshes you did not make.

    python scripts/heldout_python.py [--wmslice BIN] [--max N] MESH.stl...

For each STL file the command line accepts: its exact critical heights
(`wmslice critical`, at most N, evenly picked) and the midpoints between
them are sliced twice, by `wmslice slice --exact --format json` and by the
Python package on the file as trimesh reads it (`process=False`: three
vertices per facet, in file order, nothing merged), welded by the package
(`Mesh(..., weld=True)`, as the STL reader welds). The two documents'
`levels` must be equal, value for value: another parser, the numpy
conversion and the binding checked on real coordinates. Prints one line a
mesh; exits 1 when one differs or fails. Never commit the meshes.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import trimesh
import wmslice

import critical_levels

HERE = os.path.dirname(os.path.abspath(__file__))


def levels_of(binary, mesh, most):
    """The critical heights and the midpoints between them, as Fractions."""
    out = subprocess.run([binary, "critical", mesh, "--format", "json"], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return critical_levels.levels(json.loads(out.stdout), most)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--wmslice", default=os.path.join(HERE, "..", "target", "release", "wmslice"))
    ap.add_argument("--max", type=int, default=50)
    ap.add_argument("meshes", nargs="+")
    a = ap.parse_args()
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in a.meshes:
            name = os.path.basename(mesh)
            if not name.lower().endswith(".stl"):
                # trimesh numbers an indexed file's vertices its own way, and
                # ids choose where a loop starts: the values would differ.
                print(f"skipped  {name}: not STL")
                continue
            if subprocess.run([a.wmslice, "check", mesh], capture_output=True).returncode != 0:
                print(f"refused  {name}")
                continue
            levels = levels_of(a.wmslice, mesh, a.max)
            if not levels:
                print(f"skipped  {name}: no critical height")
                continue
            lf = os.path.join(tmp, "levels")
            with open(lf, "w") as f:
                f.write("\n".join(f"{z.numerator}/{z.denominator}" for z in levels) + "\n")
            out = os.path.join(tmp, "cli.json")
            r = subprocess.run(
                [a.wmslice, "slice", mesh, "--levels-file", lf, "--exact", "--format", "json", "--quiet", "-o", out],
                capture_output=True,
                text=True,
            )
            if r.returncode != 0:
                print(f"FAILED   {name}: cli: {r.stderr.strip()[:300]}")
                failed = True
                continue
            with open(out) as f:
                cli = json.load(f)["levels"]
            try:
                t = trimesh.load(mesh, process=False, force="mesh")
            except Exception as e:  # noqa: BLE001 - the other reader's limit
                print(f"skipped  {name}: trimesh cannot read it: {type(e).__name__}: {e}")
                continue
            if len(t.faces) == 0:
                # gmsh's ktoolcav.stl: a binary STL whose header starts
                # "solxd"; trimesh returns an empty mesh.
                print(f"skipped  {name}: trimesh reads no faces")
                continue
            try:
                m = wmslice.Mesh(t.vertices, t.faces, weld=True)
                py = json.loads(m.slice_many(levels, exact=True).to_json(exact=True))["levels"]
            except Exception as e:  # noqa: BLE001 - reported, then the next mesh
                print(f"FAILED   {name}: python: {type(e).__name__}: {e}")
                failed = True
                continue
            if py != cli:
                bad = next((i for i, (p, c) in enumerate(zip(py, cli)) if p != c), min(len(py), len(cli)))
                print(f"FAILED   {name}: level {bad} of {len(cli)} differs")
                failed = True
                continue
            print(f"agree    {name}: {len(levels)} levels, {t.faces.shape[0]} facets")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
