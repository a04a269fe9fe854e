"""Optional extras (trimesh in, shapely out) and the GIL released while
slicing."""

import threading
import time

import numpy as np
import pytest

import wmslice
from conftest import torus


def test_from_trimesh_and_to_shapely():
    trimesh = pytest.importorskip("trimesh")
    pytest.importorskip("shapely")
    box = trimesh.creation.box(extents=(2.0, 3.0, 4.0))
    m = wmslice.Mesh.from_trimesh(box)
    ls = m.slice(0)
    shape = ls.to_shapely()
    assert shape.area == 6.0 and shape.is_valid
    # Three vertices a face, as trimesh keeps an STL with process=False:
    # refused as it is, the box again once welded.
    corners = box.vertices[box.faces].reshape(-1, 3)
    soup = trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3), process=False)
    with pytest.raises(wmslice.InvalidMesh, match="open edge"):
        wmslice.Mesh.from_trimesh(soup)
    welded = wmslice.Mesh.from_trimesh(soup, weld=True)
    assert welded.welded == 36 - 8
    assert welded.slice("1/2", exact=True).contours[0].area_exact == m.slice("1/2", exact=True).contours[0].area_exact
    # An annulus: one polygon with one hole, area the sum of the signed areas.
    v, f = torus(120, 40, dtype=np.float64)
    ls = wmslice.Mesh(v, f).slice("1/3", exact=True)
    shape = ls.to_shapely()
    assert len(shape.geoms) == 1 and len(shape.geoms[0].interiors) == 1
    assert abs(shape.area - float(sum(l.area_exact for l in ls.contours))) < 1e-9 * shape.area


def test_slicing_releases_the_gil():
    v, f = torus(400, 200)
    m = wmslice.Mesh(v, f)
    zs = np.linspace(-14.9, 14.9, 400)
    started, finished = threading.Event(), threading.Event()

    def work():
        started.set()
        m.slice_many(zs, threads=1)
        finished.set()

    t = threading.Thread(target=work)
    t0 = time.perf_counter()
    t.start()
    started.wait()
    spins = 0
    while not finished.is_set():
        spins += 1
    t.join()
    elapsed = time.perf_counter() - t0
    # With the GIL held for the whole call this thread could not run while
    # it lasts (it would see `finished` at its first look).
    assert elapsed > 0.05 and spins > 1000, (elapsed, spins)
