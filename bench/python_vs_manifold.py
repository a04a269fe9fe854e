"""numpy in and out, one process: wmslice's Python package against
manifold3d on the 1 M-triangle torus (f32 vertices, centred at the origin,
tilted and turned as bench/meshgen.rs builds it) at 1000 levels.

wmslice: ``Mesh(vertices, faces)`` (validation, topology) plus
``slice_many(levels)`` plus every contour's ``points`` ndarray.
manifold3d: ``Manifold(Mesh(...))`` plus ``slice(z).to_polygons()`` per
level. The same float32 vertices, the same levels (doubles evenly spaced
strictly inside the height range). Medians of ``--runs`` runs.

    python bench/python_vs_manifold.py [--triangles 1000000] [--levels 1000] [--runs 3]
"""

import argparse
import statistics
import time

import numpy as np


def torus_of(triangles: int):
    nv = max(3, round((triangles / 5) ** 0.5))
    nu = max(3, triangles // (2 * nv))
    big, small, tilt, turn = 40.0, 15.0, 0.4, 0.3
    u = 2 * np.pi * (np.arange(nu) + 0.25) / nu
    v = 2 * np.pi * (np.arange(nv) + 0.5) / nv
    rr = big + small * np.cos(v)[:, None]
    x = rr * np.cos(u)[None, :]
    y = rr * np.sin(u)[None, :]
    z = np.broadcast_to(small * np.sin(v)[:, None], x.shape)
    y, z = y * np.cos(tilt) - z * np.sin(tilt), y * np.sin(tilt) + z * np.cos(tilt)
    x, y = x * np.cos(turn) - y * np.sin(turn), x * np.sin(turn) + y * np.cos(turn)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    j = np.arange(nv)[:, None]
    i = np.arange(nu)[None, :]
    a0, a1 = j * nu + i, j * nu + (i + 1) % nu
    b0, b1 = ((j + 1) % nv) * nu + i, ((j + 1) % nv) * nu + (i + 1) % nu
    faces = np.concatenate([np.stack([a0, a1, b1], -1).reshape(-1, 3), np.stack([a0, b1, b0], -1).reshape(-1, 3)])
    return vertices, faces.astype(np.uint32)


def run_wmslice(v, f, zs, threads):
    import wmslice

    t0, c0 = time.perf_counter(), time.process_time()
    m = wmslice.Mesh(v, f)
    many = m.slice_many(zs, threads=threads)
    n = sum(len(loop.points) for ls in many for loop in ls.contours)
    return time.perf_counter() - t0, time.process_time() - c0, n


def run_manifold(v, f, zs):
    import manifold3d

    t0, c0 = time.perf_counter(), time.process_time()
    man = manifold3d.Manifold(manifold3d.Mesh(vert_properties=v, tri_verts=f))
    n = sum(len(p) for z in zs for p in man.slice(float(z)).to_polygons())
    return time.perf_counter() - t0, time.process_time() - c0, n


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--levels", type=int, default=1000)
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    v, f = torus_of(a.triangles)
    lo, hi = float(v[:, 2].min()), float(v[:, 2].max())
    zs = np.linspace(lo, hi, a.levels + 2)[1:-1]
    print(f"torus: {len(f)} triangles, {len(v)} vertices (f32, centred), {len(zs)} levels")
    rows = [
        ("wmslice 1 thread", lambda: run_wmslice(v, f, zs, 1)),
        ("wmslice 2 threads", lambda: run_wmslice(v, f, zs, 2)),
        ("manifold3d", lambda: run_manifold(v, f, zs)),
    ]
    result = {}
    for name, fn in rows:
        times, cpu, points = [], [], None
        for _ in range(a.runs):
            t, c, n = fn()
            times.append(t)
            cpu.append(c)
            points = n
        result[name] = statistics.median(times)
        print(
            f"{name:20s} median {result[name]:.3f} s wall, {statistics.median(cpu):.3f} s CPU"
            f"  (runs {', '.join(f'{t:.3f}' for t in times)}; {points} contour points)"
        )
    for name in ("wmslice 1 thread", "wmslice 2 threads"):
        print(f"manifold3d / {name}: {result['manifold3d'] / result[name]:.2f}x")


if __name__ == "__main__":
    main()
