"""Writes the JSON of every built-in dataset and of given meshes with one
wmslice binary, so that two binaries' outputs can be compared byte for
byte (`cmp`):

    python identity.py WMSLICE OUT_DIR [--layers 300] [MESH...]
    python identity.py --compare DIR_A DIR_B

Datasets: every distinct vertex height (the degenerate levels) plus 37
uniform layers, `--format json` and `--format json --exact`. Meshes: LAYERS
uniform layers over their height, both formats (`--exact` only for meshes
under 20 000 faces: the exact text of big meshes is large).
"""

import os
import subprocess
import sys
import tempfile


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        return f"FAILED: {out.stderr.strip()[-300:]}"
    return out.stdout


def heights(binary, mesh):
    """Distinct vertex heights of a mesh, via an OBJ written by `gen` or read."""
    path = mesh
    if not os.path.exists(mesh):
        path = os.path.join(tempfile.mkdtemp(), mesh + ".obj")
        run([binary, "gen", mesh, "-o", path])
    zs = set()
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                zs.add(line.split()[3])
    return sorted(zs, key=float)


def write_all(binary, out, layers, meshes):
    os.makedirs(out, exist_ok=True)
    names = [l.split()[0] for l in run([binary, "gen", "--list"]).splitlines() if l.strip()]
    jobs = []
    for name in names:
        zs = heights(binary, name)
        levels = os.path.join(out, f"{name}.levels")
        with open(levels, "w") as f:
            f.write("\n".join(zs) + "\n")
        lo, hi = float(zs[0]), float(zs[-1])
        h = f"{(hi - lo) / 37:.6f}" if hi > lo else "1"
        jobs.append((name, ["--levels-file", levels], "deg"))
        jobs.append((name, ["--layer-height", h], "layers"))
    for mesh in meshes:
        import trimesh

        z = trimesh.load_mesh(mesh, process=False).vertices[:, 2]
        lo, hi = float(z.min()), float(z.max())
        h = f"{(hi - lo) / layers:.4g}"
        jobs.append((mesh, ["--layer-height", h], "layers"))
    for mesh, args, tag in jobs:
        stem = f"{os.path.basename(mesh)}.{tag}"
        big = os.path.exists(mesh) and os.path.getsize(mesh) > 1_000_000
        for exact in ([False] if big else [False, True]):
            dest = os.path.join(out, stem + (".exact" if exact else "") + ".json")
            cmd = [binary, "slice", mesh, *args, "--threads", "1", "--quiet", "--format", "json",
                   "-o", dest] + (["--exact"] if exact else [])
            r = run(cmd)
            if r.startswith("FAILED"):
                with open(dest, "w") as f:
                    f.write(r + "\n")
        print(stem, flush=True)


def compare(a, b):
    same = differ = 0
    for name in sorted(os.listdir(a)):
        if not name.endswith(".json"):
            continue
        other = os.path.join(b, name)
        if not os.path.exists(other):
            print(f"missing in {b}: {name}")
            differ += 1
        elif open(os.path.join(a, name), "rb").read() == open(other, "rb").read():
            same += 1
        else:
            print(f"DIFFERS: {name}")
            differ += 1
    print(f"{same} identical, {differ} different")
    return differ == 0


def main():
    if sys.argv[1] == "--compare":
        sys.exit(0 if compare(sys.argv[2], sys.argv[3]) else 1)
    binary, out = sys.argv[1], sys.argv[2]
    rest = sys.argv[3:]
    layers = 300
    if rest[:1] == ["--layers"]:
        layers = int(rest[1])
        rest = rest[2:]
    write_all(binary, out, layers, rest)


if __name__ == "__main__":
    main()
