"""The JSON is byte-equal to the command line's for the same input and
levels: every dataset at its degenerate levels and between them, uniform
layers, a file read with a snap grid, one level alone."""

from fractions import Fraction

import pytest

import wmslice


def text(levels):
    return [str(Fraction(z)) if not isinstance(z, str) else z for z in levels]


@pytest.mark.parametrize("name", [d[0] for d in wmslice.datasets()])
def test_every_dataset_equals_the_cli(cli, name):
    _, _, degenerate = next(d for d in wmslice.datasets() if d[0] == name)
    levels = sorted(set(degenerate) | {z + Fraction(1, 7) for z in degenerate})
    m = wmslice.dataset(name)
    args = [a for z in levels for a in ("--at", str(z))]
    for exact in (True, False):
        flag = ["--exact"] if exact else []
        expected = cli("slice", name, *args, "--format", "json", *flag).decode()
        assert m.slice_many(levels, exact=exact).to_json() == expected
    # One level alone, through Mesh.slice.
    z = levels[0]
    assert m.slice(z, exact=True).to_json() == cli("slice", name, "--at", str(z), "--format", "json", "--exact").decode()


def test_layers_equal_the_cli(cli):
    m = wmslice.dataset("double_torus")
    expected = cli("slice", "double_torus", "--layer-height", "0.3", "--format", "json").decode()
    assert m.slice_layers("0.3").to_json() == expected
    expected = cli("slice", "double_torus", "--layer-height", "1/4", "--first", "-1", "--last", "2", "--format", "json", "--exact").decode()
    assert m.slice_layers("1/4", first=-1, last=2, exact=True).to_json() == expected
    # to_json(exact=...) overrides how the levels were sliced.
    assert m.slice_layers("1/4", first=-1, last=2).to_json(exact=True) == expected


def test_a_snapped_file_equals_the_cli(cli, scratch):
    path = scratch / "part.stl"
    cli("gen", "lying_torus", "-o", str(path))
    m = wmslice.load(path, snap="1/10000")
    expected = cli("slice", str(path), "--snap", "1/10000", "--at", "0", "--at", "1/3", "--format", "json", "--exact").decode()
    assert m.slice_many([0, "1/3"], exact=True).to_json() == expected
    assert '"snap":"1/10000"' in expected


def test_to_json_writes_a_file_atomically(scratch):
    m = wmslice.dataset("cylinder")
    many = m.slice_many([0, 1, 2])
    out = scratch / "sub" / "c.json"
    assert many.to_json(path=out) is None
    assert out.read_text() == many.to_json()
    assert [p.name for p in out.parent.iterdir()] == ["c.json"]
    # A path given first is the path (a bool is never one), for the
    # levels and for one level; exact stays as sliced.
    first = scratch / "first.json"
    assert many.to_json(str(first)) is None and first.read_text() == many.to_json()
    assert many[1].to_json(first) is None and first.read_text() == many[1].to_json()
    exact = m.slice_many([0, 1, 2], exact=True)
    assert exact.to_json(first) is None and first.read_text() == exact.to_json(True)
    assert many.to_json(False) == many.to_json() != many.to_json(True)
