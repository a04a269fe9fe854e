"""Times the Python peers of bench/compare on one mesh and one list of levels.

    python peers.py trimesh|manifold3d MESH.stl LEVELS.txt

Prints one JSON line: load_s (read the binary STL and merge identical
vertices), build_s (the peer's own structure: the Manifold; trimesh builds
nothing ahead), slice_s (all levels, the results kept per level then
dropped) and counts. Interpreter start and imports are not timed.

- trimesh: `Trimesh.section_multiplane` (segments chained into closed
  2D paths, `Path2D.discrete`, the polylines a user gets; needs networkx
  and scipy, which bench/compare installs).
- manifold3d: `Manifold.slice(z)` per level, then `CrossSection.to_polygons()`.
  manifold3d reads no STL, so the file is read with numpy and welded with
  `numpy.unique` on the exact float32 coordinates.
"""

import json
import sys
import time

import numpy as np


def read_binary_stl(path):
    """Triangle soup (n, 3, 3) float32 of a binary STL."""
    with open(path, "rb") as f:
        f.read(80)
        n = int(np.frombuffer(f.read(4), dtype="<u4")[0])
        rec = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])
        data = np.fromfile(f, dtype=rec, count=n)
    return data["v"]


def read_obj(path):
    """Vertices (float64, as written) and triangles (0-based) of an OBJ of
    `v x y z` and `f i j k` lines."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(line[2:])
            elif line.startswith("f "):
                faces.append(line[2:])
    v = np.array(" ".join(verts).split(), dtype=np.float64).reshape(-1, 3)
    t = np.array(" ".join(faces).split(), dtype=np.int64).reshape(-1, 3) - 1
    return v, t.astype(np.uint32)


def load(path):
    """Vertices and faces: OBJ as written, binary STL welded."""
    if path.endswith(".obj"):
        return read_obj(path)
    return weld(read_binary_stl(path))


def weld(soup):
    """Vertices and faces, merging exactly equal float32 points."""
    flat = np.ascontiguousarray(soup.reshape(-1, 3))
    keys = flat.view(np.dtype((np.void, 12))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return flat[first], inverse.reshape(-1, 3).astype(np.uint32)


def run_manifold(path, levels):
    from manifold3d import Manifold, Mesh

    t = time.perf_counter()
    verts, faces = load(path)
    load_s = time.perf_counter() - t
    t = time.perf_counter()
    # manifold3d's Mesh holds float32 (an f64 OBJ is rounded to it).
    m = Manifold(Mesh(vert_properties=np.ascontiguousarray(verts, dtype=np.float32), tri_verts=faces))
    status = str(m.status())
    tris = m.num_tri()
    build_s = time.perf_counter() - t
    if tris != len(faces):
        raise SystemExit(f"manifold3d rejected the mesh: {status}")
    t = time.perf_counter()
    loops = points = 0
    for z in levels:
        polys = m.slice(z).to_polygons()
        loops += len(polys)
        points += sum(len(p) for p in polys)
    slice_s = time.perf_counter() - t
    return dict(triangles=tris, load_s=load_s, build_s=build_s, slice_s=slice_s,
                contours=loops, points=points)


def run_trimesh(path, levels):
    import trimesh

    t = time.perf_counter()
    mesh = trimesh.load_mesh(path)  # merges identical vertices
    load_s = time.perf_counter() - t
    t = time.perf_counter()
    sections = mesh.section_multiplane(
        plane_origin=[0.0, 0.0, 0.0], plane_normal=[0.0, 0.0, 1.0], heights=levels
    )
    loops = points = 0
    for s in sections:
        if s is None:
            continue
        curves = s.discrete  # chains the segments into closed polylines
        loops += len(curves)
        points += sum(len(c) for c in curves)
    slice_s = time.perf_counter() - t
    return dict(triangles=len(mesh.faces), load_s=load_s, build_s=0.0, slice_s=slice_s,
                contours=loops, points=points)


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("trimesh", "manifold3d"):
        raise SystemExit(__doc__)
    levels = [float(x) for x in open(sys.argv[3]).read().split()]
    run = run_trimesh if sys.argv[1] == "trimesh" else run_manifold
    result = run(sys.argv[2], levels)
    result["levels"] = len(levels)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
