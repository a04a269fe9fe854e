"""Meshes from numpy arrays and files: dtypes, answers derived by hand on
the unit cube, and every error as a typed Python exception."""

import json
import math
import pickle
from fractions import Fraction

import numpy as np
import pytest

import wmslice
from conftest import torus, unit_cube


def shoelace(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def test_cube_at_half_is_the_unit_square():
    m = wmslice.Mesh(*unit_cube())
    ls = m.slice("1/2", exact=True)
    assert len(ls.contours) == 1
    (loop,) = ls.contours
    assert loop.points.dtype == np.float64 and loop.points.ndim == 2 and loop.points.shape[1] == 2
    # Four vertical edges and four side diagonals cross z = 1/2.
    assert len(loop.points) == 8
    assert {tuple(p) for p in loop.points} >= {(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)}
    on_square = (np.isin(loop.points[:, 0], [0, 1]) | np.isin(loop.points[:, 1], [0, 1])).all()
    assert on_square
    assert loop.area_exact == 1 and loop.area == 1.0 and shoelace(loop.points) == 1.0
    assert loop.role == "outer" and loop.parent is None and not loop.collapsed
    assert all(kind in ("edge", "vertex") for kind, _ in loop.on)
    assert [(float(x), float(y)) for x, y in loop.exact] == [tuple(p) for p in loop.points]
    # No vertex on the plane: L- and L+ are S_O.
    assert [l.area for l in ls.below] == [1.0] and [l.area for l in ls.above] == [1.0]
    assert ls.faces == [] and ls.ridges == [] and ls.points == [] and ls.saddles == []


def test_cube_at_its_top_and_bottom_faces():
    m = wmslice.Mesh(*unit_cube())
    top = m.slice(1)
    assert top.contours == []
    (region,) = top.faces
    assert region.facing == "up" and list(region.faces) == [2, 3] and region.area == 1
    assert [l.area for l in region.boundary] == [1.0]
    assert [l.area for l in top.below] == [1.0] and top.above == []
    bottom = m.slice(0.0)
    (region,) = bottom.faces
    assert region.facing == "down" and list(region.faces) == [0, 1]
    assert bottom.below == [] and [l.area for l in bottom.above] == [1.0]


def test_dtypes_in_give_the_same_level_sets():
    v, f = torus(40, 12)
    ref = wmslice.Mesh(v.astype(np.float64), f).slice_many([0, 3, "7/2"], exact=True).to_json()
    for vv in (v, v.astype(np.float64), np.asfortranarray(v), v.astype(np.float64)[:, [0, 1, 2]]):
        for ff in (f, f.astype(np.int32), f.astype(np.uint32), f.astype(np.uint64), np.asfortranarray(f)):
            assert wmslice.Mesh(vv, ff).slice_many([0, 3, "7/2"], exact=True).to_json() == ref
    # Lists work too.
    assert wmslice.Mesh(v.tolist(), f.tolist()).slice_many([0, 3, "7/2"], exact=True).to_json() == ref


def test_float32_vertices_are_taken_exactly():
    v, f = torus(30, 10)
    m = wmslice.Mesh(v, f)
    assert np.array_equal(m.vertices, v.astype(np.float64))
    assert m.faces.dtype == np.uint32 and np.array_equal(m.faces, f)
    assert m.z_range == (Fraction(float(v[:, 2].min())), Fraction(float(v[:, 2].max())))


def test_an_open_mesh_is_refused_by_name():
    v, f = unit_cube()
    with pytest.raises(wmslice.InvalidMesh) as e:
        wmslice.Mesh(v, f[:-1])  # one triangle of the x = 1 side removed
    assert isinstance(e.value, ValueError)
    kinds = {d["kind"] for d in e.value.defects}
    assert kinds == {"open_edge"}
    # The triangle (3, 7, 5) is gone: its three edges are open, each named.
    edges = {frozenset((d["a"], d["b"])) for d in e.value.defects}
    assert edges == {frozenset((3, 7)), frozenset((7, 5)), frozenset((5, 3))}
    assert "open edge" in str(e.value)
    assert str(e.value).startswith("invalid mesh (3 blocking defects): ")
    assert (e.value.unlisted, e.value.unlisted_count) == (0, "exact")


def test_a_nan_coordinate_is_refused_by_vertex():
    v, f = unit_cube()
    v[5, 2] = np.nan
    with pytest.raises(ValueError) as e:
        wmslice.Mesh(v, f)
    assert isinstance(e.value, wmslice.InvalidMesh)
    assert e.value.defects[0]["kind"] == "non_finite_coordinate"
    assert e.value.defects[0]["vertex"] == 5
    assert "v5" in str(e.value)
    assert str(e.value).startswith("invalid mesh (1 blocking defect): ")
    # Snapping refuses it by name as well.
    with pytest.raises(wmslice.InvalidMesh, match="v5"):
        wmslice.Mesh(v, f, snap="1/100")


def test_bad_indices_and_shapes():
    v, f = unit_cube()
    g = f.copy()
    g[4, 1] = -1
    with pytest.raises(wmslice.InvalidMesh) as e:
        wmslice.Mesh(v, g)
    assert e.value.defects[0]["kind"] == "index_out_of_range"
    assert (e.value.defects[0]["face"], e.value.defects[0]["corner"]) == (4, 1)
    g[4, 1] = 8
    with pytest.raises(wmslice.InvalidMesh, match="f4"):
        wmslice.Mesh(v, g)
    with pytest.raises(ValueError):
        wmslice.Mesh(v[:, :2], f)
    with pytest.raises(ValueError):
        wmslice.Mesh(v, f[:, :2])
    with pytest.raises(TypeError):
        wmslice.Mesh(v, f.astype(np.float64))
    with pytest.raises(wmslice.InvalidMesh, match="no faces"):
        wmslice.Mesh(v, np.zeros((0, 3), dtype=np.int64))


def test_inside_out_is_refused():
    v, f = unit_cube()
    with pytest.raises(wmslice.InvalidMesh) as e:
        wmslice.Mesh(v, f[:, ::-1])
    assert [d["kind"] for d in e.value.defects if d["severity"] == "error"] == ["not_outward"]


def test_files_every_format_and_errors(cli, scratch):
    for ext in ("stl", "obj", "off", "ply"):
        path = scratch / f"t.{ext}"
        cli("gen", "double_torus", "-o", str(path))
        m = wmslice.load(str(path))
        expected = cli("slice", str(path), "--at", "0", "--at", "1", "--format", "json", "--exact")
        assert m.slice_many([0, 1], exact=True).to_json().encode() == expected
    # OBJ, OFF and PLY keep the dataset's vertex order: the same mesh hash.
    assert wmslice.load(scratch / "t.off").sha256 == wmslice.dataset("double_torus").sha256
    with pytest.raises(FileNotFoundError):
        wmslice.load(scratch / "missing.stl")
    bad = scratch / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n")
    with pytest.raises(ValueError):
        wmslice.load(bad)
    with pytest.raises(ValueError):
        wmslice.dataset("no_such_dataset")


def test_a_file_in_memory_or_open_loads_as_the_file(cli, scratch):
    """Bytes, a bytearray, a memoryview, an open binary file and a BytesIO
    give the mesh the path gives (format by content), in every format."""
    import io

    for ext in ("stl", "obj", "off", "ply"):
        path = scratch / f"t.{ext}"
        cli("gen", "double_torus", "-o", str(path))
        want = wmslice.load(path)
        data = path.read_bytes()
        with open(path, "rb") as f:
            opened = wmslice.load(f)
        for got in (
            wmslice.load(data),
            wmslice.load(bytearray(data)),
            wmslice.load(memoryview(data)),
            wmslice.load(io.BytesIO(data)),
            opened,
        ):
            assert got.sha256 == want.sha256, ext
            assert got.slice_many([2, 4], exact=True).to_json() == want.slice_many([2, 4], exact=True).to_json()
    with open(scratch / "t.obj") as text:
        with pytest.raises(TypeError, match="open it with 'rb'"):
            wmslice.load(text)
    with pytest.raises(ValueError, match="empty"):
        wmslice.load(b"")
    with pytest.raises(ValueError, match="unknown mesh format"):
        wmslice.load(b"not a mesh")


def test_a_3mf_placed_by_a_rounding_transform_loads_only_on_a_grid(cli, scratch):
    """The unit cube at decimal offsets, placed by a build item's
    translation: 0.1 + 125 is not a double, so the file is refused without
    a grid and snapped from the exact image on one, as the CLI does."""
    import zipfile

    v, f = unit_cube()
    vertices = "".join(
        f'<vertex x="{float(x) / 10 + 0.1!r}" y="{y:g}" z="{z:g}"/>' for x, y, z in v
    )
    triangles = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in f)
    xml = (
        '<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" '
        'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>'
        f'<object id="1" type="model"><mesh><vertices>{vertices}</vertices>'
        f"<triangles>{triangles}</triangles></mesh></object></resources>"
        '<build><item objectid="1" transform="1 0 0 0 1 0 0 0 1 125 0 0"/></build></model>'
    )
    path = scratch / "placed.3mf"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("3D/3dmodel.model", xml)
    with pytest.raises(ValueError, match="snap to a grid"):
        wmslice.load(path)
    m = wmslice.load(path, snap="1/100")
    # x in {125.1, 125.2}: the grid points 12510 and 12520 exactly; the
    # diagonals of the faces y = 0 and y = 1 cross z = 1/2 halfway.
    ls = m.slice("1/2", exact=True)
    xs = {float(x) for x, _ in ls.contours[0].points}
    assert xs == {125.1, 125.15, 125.2}
    expected = cli("slice", str(path), "--snap", "1/100", "--at", "1/2", "--format", "json", "--exact")
    assert ls.to_json().encode() == expected


def test_snap_moves_to_the_grid_and_is_reported():
    v, f = unit_cube()
    v = v * np.float32(0.6)  # 0.6 as a float32 times the corners: not multiples of 1/10
    m = wmslice.Mesh(v.astype(np.float32), f, snap="1/10")
    assert m.snap == "1/10"
    assert m.snap_report["moved"] > 0 and m.snap_report["grid"] == Fraction(1, 10)
    ls = m.slice("0.6", exact=True)
    (region,) = ls.faces
    assert region.facing == "up" and region.area == Fraction(9, 25)
    assert math.isclose(m.vertices.max(), 0.6)


def test_overlapping_and_touching_bodies_are_refused_by_a_face_pair():
    # Two unit cubes in one mesh (SPEC 1): the second moved by (1/2, 1/2,
    # 1/2) overlaps the first, moved by (1, 0, 0) it touches it along the
    # face x = 1 without sharing vertices; both are refused, naming a face
    # of each cube (faces 0-11 and 12-23). Moved by (2, 0, 0) they are
    # apart: accepted, and the plane z = 1/2 cuts two unit squares.
    v, f = unit_cube()
    for shift in ([0.5, 0.5, 0.5], [1.0, 0.0, 0.0]):
        vv = np.vstack([v, v + np.array(shift)])
        ff = np.vstack([f, f + len(v)])
        with pytest.raises(wmslice.InvalidMesh, match="intersect") as e:
            wmslice.Mesh(vv, ff)
        pairs = [(d["a"], d["b"]) for d in e.value.defects if d["kind"] == "self_intersection"]
        assert pairs, e.value.defects
        assert all(a < 12 <= b for a, b in pairs)
    apart = wmslice.Mesh(np.vstack([v, v + np.array([2.0, 0.0, 0.0])]), np.vstack([f, f + len(v)]))
    ls = apart.slice("1/2", exact=True)
    assert sorted(l.area_exact for l in ls.contours) == [1, 1]


def test_a_soup_of_crossing_faces_is_refused_with_a_bounded_count():
    # A closed torus's faces with every vertex moved to a random point:
    # more crossing pairs than validation counts (10 000), so the count is
    # a lower bound, and the listed pairs are the first ones all the same.
    v, f = torus(16, 16)
    v = np.random.default_rng(5).integers(0, 1024, size=v.shape) / 1024.0
    with pytest.raises(wmslice.InvalidMesh, match="intersect") as e:
        wmslice.Mesh(v, f)
    assert e.value.unlisted_count == "at_least"
    assert str(e.value).startswith("invalid mesh (at least ")
    pairs = [(d["a"], d["b"]) for d in e.value.defects if d["kind"] == "self_intersection"]
    assert len(pairs) == 1000 and pairs == sorted(pairs)
    assert e.value.unlisted >= 9000


def cube_with_a_near_vertex():
    """The unit cube with vertex 0 copied a hair away (vertex 8), face 4
    moved onto the copy and the gap closed by two slivers (faces 12, 13)
    that snapping to 1/1000000 collapses: each then uses vertex 0 twice."""
    v, f = unit_cube()
    v2 = np.vstack([v, [[1e-9, 0.0, 2e-9]]])
    f2 = np.vstack([f, [[0, 1, 8], [0, 8, 4]]])
    assert list(f2[4]) == [0, 1, 4]
    f2[4] = [8, 1, 4]
    return (v, f), (v2, f2)


def test_faces_snapping_collapses_are_dropped_when_asked():
    (v, f), (v2, f2) = cube_with_a_near_vertex()
    with pytest.raises(wmslice.InvalidMesh, match="repeats a vertex"):
        wmslice.Mesh(v2, f2, snap="1/1000000")
    m = wmslice.Mesh(v2, f2, snap="1/1000000", drop_collapsed=True)
    cube = wmslice.Mesh(v, f, snap="1/1000000")
    assert m.dropped == [12, 13] and cube.dropped is None
    # What is left is the cube itself: the same faces, hash and level sets.
    assert np.array_equal(m.faces, cube.faces) and m.sha256 == cube.sha256
    levels = [0, "1/2", 1]
    got = json.loads(m.slice_many(levels, exact=True).to_json())
    want = json.loads(cube.slice_many(levels, exact=True).to_json())
    assert got["levels"] == want["levels"]
    assert got["mesh"]["dropped_collapsed"] == 2 and "dropped_collapsed" not in want["mesh"]
    # Pickled, the mesh and its levels keep the count in their header.
    m2 = pickle.loads(pickle.dumps(m))
    assert m2.dropped == [12, 13]
    assert m2.slice_many(levels, exact=True).to_json() == m.slice_many(levels, exact=True).to_json()
    back = pickle.loads(pickle.dumps(m.slice_many(levels, exact=True)))
    assert json.loads(back.to_json())["mesh"]["dropped_collapsed"] == 2


def test_a_grid_coarser_than_the_part_is_named_with_its_size():
    # A 0.2 mm tetrahedron in metres on a millimetre grid: every corner
    # lands on the origin, every face collapses and is dropped.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float) * 2e-4
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(wmslice.InvalidMesh, match="much finer than the mesh") as e:
        wmslice.Mesh(v, f, snap="1/1000", drop_collapsed=True)
    assert e.value.defects[0]["kind"] == "snap_collapsed_everything"
    assert e.value.defects[0]["faces"] == 4 and e.value.defects[0]["grid"] == "1/1000"
    assert e.value.defects[0]["span"] == [2e-4, 2e-4, 2e-4]
    assert wmslice.Mesh(v, f, snap="1/1000000", drop_collapsed=True).dropped == []
    # Without dropping, the same one reason (not four faces repeating a vertex).
    with pytest.raises(wmslice.InvalidMesh, match="much finer than the mesh") as e:
        wmslice.Mesh(v, f, snap="1/1000")
    assert [d["kind"] for d in e.value.defects] == ["snap_collapsed_everything"]


def face_by_face_tetra():
    """The unit tetrahedron written with every face on its own three
    vertices (twelve; one copy of the origin with -0), and the tetrahedron
    those vertices weld to, by hand: vertices in first-seen order."""
    o, x, y, z = [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]
    v = np.array([o, y, x, o, x, z, [0.0, -0.0, 0.0], z, y, x, y, z])
    f = np.arange(12).reshape(4, 3)
    welded = (np.array([o, y, x, z]), np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [2, 1, 3]]))
    return (v, f), welded


def test_a_mesh_written_face_by_face_is_welded_when_asked(scratch):
    (v, f), (wv, wf) = face_by_face_tetra()
    with pytest.raises(wmslice.InvalidMesh, match="open edge"):
        wmslice.Mesh(v, f)
    m = wmslice.Mesh(v, f, weld=True)
    tetra = wmslice.Mesh(wv, wf)
    assert m.welded == 8 and tetra.welded is None
    assert np.array_equal(m.vertices, wv) and np.array_equal(m.faces, wf) and m.sha256 == tetra.sha256
    levels = [0, "1/2", 1]
    got = json.loads(m.slice_many(levels, exact=True).to_json())
    want = json.loads(tetra.slice_many(levels, exact=True).to_json())
    assert got["levels"] == want["levels"]
    assert got["mesh"]["welded"] == 8 and "welded" not in want["mesh"]
    (loop,) = m.slice("1/2", exact=True).contours
    assert sorted(loop.exact) == [(0, 0), (0, Fraction(1, 2)), (Fraction(1, 2), 0)]
    # Pickled, the mesh and its levels keep the count.
    assert pickle.loads(pickle.dumps(m)).welded == 8
    back = pickle.loads(pickle.dumps(m.slice_many(levels, exact=True)))
    assert json.loads(back.to_json())["mesh"]["welded"] == 8
    # From a file, as the command line reads it.
    path = scratch / "faces.obj"
    path.write_text(
        "".join(f"v {a!r} {b!r} {c!r}\n" for a, b, c in v.tolist())
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f.tolist())
    )
    with pytest.raises(wmslice.InvalidMesh, match="open edge"):
        wmslice.load(path)
    assert wmslice.load(path, weld=True).sha256 == tetra.sha256


def test_a_file_with_faces_snapping_collapses_loads_when_asked(scratch):
    (v, f), (v2, f2) = cube_with_a_near_vertex()
    path = scratch / "near.obj"
    path.write_text(
        "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v2.tolist())
        + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f2.tolist())
    )
    with pytest.raises(wmslice.InvalidMesh, match="repeats a vertex"):
        wmslice.load(path, snap="1/1000000")
    m = wmslice.load(path, snap="1/1000000", drop_collapsed=True)
    assert m.dropped == [12, 13]
    assert m.sha256 == wmslice.Mesh(v, f, snap="1/1000000").sha256
