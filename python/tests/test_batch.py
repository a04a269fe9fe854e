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
