"""Levels are exact: a float is its binary value, a str goes through the
exact parser, ints and Fractions are exact; bad levels are ValueErrors."""

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

import wmslice
from conftest import torus, unit_cube


def test_a_float_is_its_exact_binary_value():
    m = wmslice.Mesh(*unit_cube())
    assert m.slice(0.1).z == Fraction(0.1) == Fraction(3602879701896397, 36028797018963968)
    assert m.slice("0.1").z == Fraction(1, 10)
    assert m.slice(Fraction(3, 5)).z == m.slice("3/5").z == m.slice("0.6").z == Fraction(3, 5)
    assert m.slice(Decimal("0.6")).z == Fraction(3, 5)
    assert m.slice(np.float32(0.5)).z == Fraction(1, 2)
    assert m.slice(np.int64(1)).z == 1
    assert wmslice.exact_value(2**80) == 2**80


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), "abc", "1/0", True, None, [1], Decimal("nan")])
def test_bad_levels_are_value_errors(bad):
    m = wmslice.Mesh(*unit_cube())
    with pytest.raises(ValueError):
        m.slice(bad)


def test_slice_many_sorts_and_dedups_like_the_cli():
    m = wmslice.Mesh(*unit_cube())
    many = m.slice_many(["1/2", 0, 0.5, Fraction(1, 4), 1])
    assert many.levels == [0, Fraction(1, 4), Fraction(1, 2), 1]
    with pytest.raises(ValueError):
        m.slice_many([])
    with pytest.raises(ValueError):
        m.slice_many(np.array([0.5, np.nan]))
    with pytest.raises(ValueError):
        m.slice_many([0.5], threads=0)
    # More workers than 4 a core (and 256) would spend their time looking
    # for work: 40 000 did not finish the unit cube in 100 s. Refused.
    with pytest.raises(ValueError, match="at most"):
        m.slice_many([0.5], threads=1_000_000)


def test_numpy_levels_and_threads_give_the_same_result():
    v, f = torus(60, 20)
    m = wmslice.Mesh(v, f)
    zs = np.linspace(-15, 15, 41)
    a = m.slice_many(zs, threads=1)
    b = m.slice_many(list(zs), threads=2)
    c = m.slice_many(zs.astype(np.float32).astype(np.float64), threads=3)
    assert a.to_json() == b.to_json()
    assert a.levels == [Fraction(z) for z in zs]
    assert len(c) == 41
    for x, y in zip(a, b):
        for l1, l2 in zip(x.contours, y.contours):
            assert np.array_equal(l1.points, l2.points) and l1.area == l2.area


def test_layers_are_exact_and_mid_layer():
    m = wmslice.Mesh(*unit_cube())
    levels = m.layer_levels("0.2")
    assert levels == [Fraction(1, 10), Fraction(3, 10), Fraction(1, 2), Fraction(7, 10), Fraction(9, 10)]
    assert m.slice_layers("0.2").levels == levels
    assert m.layer_levels("1/4", first=0, last="1/2") == [0, Fraction(1, 4), Fraction(1, 2)]
    with pytest.raises(ValueError):
        m.layer_levels(0)


def test_torus_areas_are_right_and_holes_nested():
    v, f = torus(200, 60, dtype=np.float64)
    m = wmslice.Mesh(v, f)
    ls = m.slice(0, exact=True)
    outer = [l for l in ls.contours if l.role == "outer"]
    holes = [l for l in ls.contours if l.role == "hole"]
    assert len(outer) == 1 and len(holes) == 1
    assert holes[0].parent == ls.contours.index(outer[0])
    assert outer[0].area > 0 > holes[0].area
    for loop in ls.contours:
        # `area` is the nearest double of the exact area (Python's float of a
        # Fraction is correctly rounded), and the shoelace of the rounded
        # points agrees to rounding.
        assert loop.area == float(loop.area_exact)
        x, y = loop.points[:, 0], loop.points[:, 1]
        shoelace = 0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
        assert abs(shoelace - loop.area) <= 1e-9 * abs(loop.area)
        # Each rounded point is the nearest double of its exact point.
        assert [(float(a), float(b)) for a, b in loop.exact] == [tuple(p) for p in loop.points]
    # The annulus lies between the circles of radii 25 and 55.
    r = np.hypot(*np.concatenate([l.points for l in ls.contours]).T)
    assert r.min() > 24.9 and r.max() < 55.0
