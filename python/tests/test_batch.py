"""Batches: one JSON document and certificate per part, equal to the
command line's, on the local cores and on a 2-worker dask LocalCluster;
a part split into shards is joined in level order to the same bytes."""

import json
import os

import pytest

import wmslice
from wmslice.batch import slice_files

PARTS = ("double_torus", "lying_torus", "peg_cube")


@pytest.fixture
def parts(cli, scratch):
    paths = []
    for name in PARTS:
        p = scratch / "in" / f"{name}.stl"
        p.parent.mkdir(exist_ok=True)
        cli("gen", name, "-o", str(p))
        paths.append(str(p))
    return paths


def expected(cli, path, out, cert, *flags):
    cli("slice", path, "--layer-height", "0.1", "--format", "json", *flags, "-o", str(out), "--certificate", str(cert))
    return out.read_bytes(), json.loads(cert.read_text())


def check(cli, scratch, paths, results, out_dir, *flags):
    assert [r["input"] for r in results] == paths
    assert sorted(os.listdir(out_dir)) == sorted(
        [f"{n}.json" for n in PARTS] + [f"{n}.cert.json" for n in PARTS]
    )
    for path, r in zip(paths, results):
        want, want_cert = expected(cli, path, scratch / "cli.json", scratch / "cli.cert.json", *flags)
        got = open(r["output"], "rb").read()
        assert got == want
        cert = json.loads(open(r["certificate"]).read())
        for key in ("format", "input", "mesh", "numeric", "levels", "verification"):
            if key == "input":
                assert cert[key]["sha256"] == want_cert[key]["sha256"]
            else:
                assert cert[key] == want_cert[key], key
        for key in ("sha256", "bytes", "verified_document_sha256"):
            assert cert["result"][key] == want_cert["result"][key], key
        assert r["levels"] == len(cert["levels"]) > 10
        assert cert["verification"]["verdict"] == "pass"


def test_local_batch(cli, scratch, parts):
    out = scratch / "out"
    results = slice_files(parts, out, layer_height="0.1")
    check(cli, scratch, parts, results, out)


def test_dask_local_cluster_with_shards(cli, scratch, parts):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            out = scratch / "out"
            results = slice_files(parts, out, layer_height="0.1", client=client)
            check(cli, scratch, parts, results, out)
            # Shards of 7 levels, joined in order: the same bytes, exact or not.
            for exact in (False, True):
                out2 = scratch / f"out-shards-{exact}"
                results = slice_files(parts, out2, layer_height="0.1", client=client, levels_per_task=7, exact=exact)
                check(cli, scratch, parts, results, out2, *(["--exact"] if exact else []))


def test_batch_errors(cli, scratch, parts):
    with pytest.raises(ValueError):
        slice_files(parts, scratch / "o", layer_height=None)
    with pytest.raises(FileNotFoundError):
        slice_files([str(scratch / "missing.stl")], scratch / "o", layer_height="0.1")
    bad = scratch / "in" / "open.off"
    # A tetrahedron without its bottom face: open.
    bad.write_text("OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n")
    with pytest.raises(wmslice.InvalidMesh):
        slice_files([str(bad)], scratch / "o", layer_height="0.1")
    # Nothing half-written.
    assert not any(p.name.startswith("open") for p in (scratch / "o").iterdir())
    # Two parts that would write one file: one stem in two folders, and a
    # part whose JSON would be another's certificate. Refused before any
    # work, naming the file.
    twin = scratch / "twin" / os.path.basename(parts[0])
    twin.parent.mkdir(exist_ok=True)
    twin.write_bytes(open(parts[0], "rb").read())
    clash = scratch / "in" / "double_torus.cert.stl"
    clash.write_bytes(open(parts[0], "rb").read())
    for pair, name in (([parts[0], str(twin)], "double_torus.json"), ([parts[0], str(clash)], "double_torus.cert.json")):
        with pytest.raises(ValueError, match=name.replace(".", r"\.")):
            slice_files(pair, scratch / "clash", layer_height="0.1")
        assert not (scratch / "clash").exists() or not any((scratch / "clash").iterdir())
    # Without certificates the second pair writes two distinct files.
    slice_files([parts[0], str(clash)], scratch / "nocert", layer_height="0.1", certificate=False)
    assert sorted(os.listdir(scratch / "nocert")) == ["double_torus.cert.json", "double_torus.json"]


def near_cube(scratch):
    """The unit cube with vertex 0 copied a hair away and two slivers that
    snapping to 1/1000000 collapses (as in test_mesh.py), as an OBJ file."""
    v = [[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)] + [[1e-9, 0.0, 2e-9]]
    f = [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [8, 1, 4], [1, 5, 4],
         [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5], [0, 1, 8], [0, 8, 4]]
    p = scratch / "in" / "near.obj"
    p.parent.mkdir(exist_ok=True)
    p.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f))
    return str(p)


def test_batch_drops_collapsed_faces_as_the_command_line_does(cli, scratch):
    path = near_cube(scratch)
    flags = ("--snap", "1/1000000", "--drop-collapsed")
    want, want_cert = expected(cli, path, scratch / "cli.json", scratch / "cli.cert.json", *flags)
    assert json.loads(want)["mesh"]["dropped_collapsed"] == 2
    with pytest.raises(wmslice.InvalidMesh, match="repeats a vertex"):
        slice_files([path], scratch / "refused", layer_height="0.1", snap="1/1000000")
    (r,) = slice_files([path], scratch / "out", layer_height="0.1", snap="1/1000000", drop_collapsed=True)
    assert open(r["output"], "rb").read() == want
    assert json.loads(open(r["certificate"]).read())["mesh"] == want_cert["mesh"]
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            (r,) = slice_files(
                [path], scratch / "shards", layer_height="0.1", snap="1/1000000", drop_collapsed=True,
                client=client, levels_per_task=3,
            )
            assert open(r["output"], "rb").read() == want


def test_batch_welds_as_the_command_line_does(cli, scratch):
    # The unit tetrahedron with each face on its own three vertices.
    o, x, y, z = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
    v = [o, y, x, o, x, z, o, z, y, x, y, z]
    p = scratch / "in" / "faces.obj"
    p.parent.mkdir(exist_ok=True)
    p.write_text("".join(f"v {a} {b} {c}\n" for a, b, c in v) + "".join(f"f {3 * i + 1} {3 * i + 2} {3 * i + 3}\n" for i in range(4)))
    path = str(p)
    want, want_cert = expected(cli, path, scratch / "cli.json", scratch / "cli.cert.json", "--weld")
    assert json.loads(want)["mesh"]["welded"] == 8
    with pytest.raises(wmslice.InvalidMesh, match="open edge"):
        slice_files([path], scratch / "refused", layer_height="0.1")
    (r,) = slice_files([path], scratch / "out", layer_height="0.1", weld=True)
    assert open(r["output"], "rb").read() == want
    assert json.loads(open(r["certificate"]).read())["mesh"] == want_cert["mesh"]
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            (r,) = slice_files([path], scratch / "shards", layer_height="0.1", weld=True, client=client, levels_per_task=3)
            assert open(r["output"], "rb").read() == want

