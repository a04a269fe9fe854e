"""Meshes and results pickle exactly: the same JSON, points and exact
values after a round trip."""

import pickle

import numpy as np

import wmslice
from conftest import torus


def test_mesh_pickles_and_is_validated_again():
    v, f = torus(40, 12)
    m = wmslice.Mesh(v, f, snap="1/1000")
    m2 = pickle.loads(pickle.dumps(m))
    assert m2.sha256 == m.sha256 and m2.snap == "1/1000" and m2.snap_report == m.snap_report
    assert np.array_equal(m2.faces, m.faces)
    assert m2.slice_many([0, 1], exact=True).to_json() == m.slice_many([0, 1], exact=True).to_json()


def test_results_pickle_exactly():
    m = wmslice.dataset("saddle8")
    _, _, levels = next(d for d in wmslice.datasets() if d[0] == "saddle8")
    many = m.slice_many(levels + [levels[0] + 1], exact=True)
    back = pickle.loads(pickle.dumps(many))
    assert sum(len(ls.saddles) for ls in many) > 0 and sum(len(ls.contours) for ls in many) > 0
    assert back.to_json() == many.to_json()
    assert back.to_json(exact=False) == many.to_json(exact=False)
    for a, b in zip(many, back):
        assert a.z == b.z
        for fam in ("contours", "below", "above"):
            for x, y in zip(getattr(a, fam), getattr(b, fam)):
                assert np.array_equal(x.points, y.points)
                assert (x.area, x.role, x.parent, x.collapsed) == (y.area, y.role, y.parent, y.collapsed)
                assert x.exact == y.exact and x.on == y.on and x.area_exact == y.area_exact
        assert [s.vertex for s in a.saddles] == [s.vertex for s in b.saddles]
    # A loop alone, and a level with its views already made.
    loop = next(l for ls in many for l in ls.contours)
    lp = pickle.loads(pickle.dumps(loop))
    assert np.array_equal(lp.points, loop.points) and lp.area_exact == loop.area_exact
    one = pickle.loads(pickle.dumps(many[0]))
    assert one.to_json() == many[0].to_json()


def test_a_corrupted_pickle_is_refused():
    m = wmslice.dataset("cylinder")
    level = m.slice(1)._level
    fn, (data,) = level.__reduce__()
    import pytest

    with pytest.raises(ValueError):
        fn(data[:-3])
    with pytest.raises(ValueError):
        fn(b"x" + data[1:])


def test_a_level_pickle_holding_a_point_beyond_any_double_is_refused():
    # Found by mutating pickles: a point's power of two set to 2^30 was
    # decoded, and its exact value (2^30 bits wide) never finished. Every
    # 4-byte window of the bytes set to 2^30: the windows on a point's
    # exponent are refused by name, and none decodes to such a point.
    m = wmslice.dataset("cylinder")
    fn, (data,) = m.slice(1, exact=True)._level.__reduce__()
    big = (1 << 30).to_bytes(4, "little")
    refused = 0
    for i in range(len(data) - 3):
        try:
            fn(data[:i] + big + data[i + 4:])
        except ValueError as e:
            refused += "point exponent" in str(e)
    assert refused > 0


def test_a_mesh_pickle_with_a_grid_not_positive_is_refused():
    # Found by mutating pickles: a snap grid of 0 panicked (a zero
    # denominator) instead of being refused.
    v, f = torus(40, 12)
    restore, args = wmslice.Mesh(v, f, snap="1/1000")._m.__reduce__()
    import pytest

    for grid in ("0", "-1/1000"):
        snap = (grid,) + tuple(args[2][1:])
        with pytest.raises(ValueError, match="grid"):
            restore(args[0], args[1], snap, *args[3:])
    assert restore(*args).sha256 == wmslice.Mesh(v, f, snap="1/1000").sha256
