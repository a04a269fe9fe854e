"""Critical heights and the Reeb graph from Python (``Mesh.critical``).

Expected values are derived by hand in ``tests/critical.rs`` (the genus-2
slab: a bottom plateau, a pit, a monkey saddle, a mixed top) and
``tests/critical_plans.rs`` (peg_cube's flats at 0, 1, 3, 7/2, 4).
"""

from fractions import Fraction

import pytest

import wmslice


def test_the_double_torus_reeb_graph():
    d = wmslice.dataset("double_torus").critical()
    assert d["format"] == "wmslice-critical"
    assert (d["genus"], d["components"]) == (2, 1)
    assert [l["z"] for l in d["critical"]] == ["0", "1", "2", "4"]
    assert d["critical"][2]["saddles"] == [3]
    assert [(l["below"], l["above"]) for l in d["critical"]] == [(0, 3), (3, 4), (4, 2), (2, 0)]
    assert [n["kind"] for n in d["reeb"]["nodes"]] == ["plateau", "min", "saddle", "mixed"]
    assert d["reeb"]["arcs"] == [[0, 2], [0, 2], [0, 3], [1, 2], [2, 3]]


def test_fitted_layers_put_every_flat_on_a_boundary():
    d = wmslice.dataset("peg_cube").critical(layer_height="0.3", fit=True)
    layers = [(Fraction(a), Fraction(b)) for a, b in d["layers"]]
    assert layers[0][0] == 0 and layers[-1][1] == 4
    assert all(b == c for (_, b), (c, _) in zip(layers, layers[1:]))
    h = Fraction(3, 10)
    assert all(h / 2 <= b - a <= 3 * h / 2 for a, b in layers)
    tops = {b for _, b in layers}
    assert {Fraction(1), Fraction(3), Fraction(7, 2), Fraction(4)} <= tops


def test_the_uniform_audit_and_errors():
    d = wmslice.dataset("peg_cube").critical(layer_height="0.3")
    assert d["first"] == "3/20"
    offsets = {(a["z"], a["facing"]): a["offset"] for a in d["audit"]}
    assert offsets[("1", "down")] == "-1/10"
    assert offsets[("7/2", "up")] == "1/10"
    with pytest.raises(ValueError, match="closer than half"):
        wmslice.dataset("peg_cube").critical(layer_height="1.1", fit=True)
    with pytest.raises(ValueError):
        wmslice.dataset("peg_cube").critical(fit=True)
