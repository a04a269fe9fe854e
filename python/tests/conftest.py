"""Shared fixtures: the command-line binary (the reference the JSON must
equal byte for byte), meshes built in numpy, and a scratch directory."""

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def _target_dir() -> Path:
    return Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))


@pytest.fixture(scope="session")
def wmslice_bin() -> str:
    """The `wmslice` binary: $WMSLICE_BIN, else the debug build (made here
    with cargo when missing)."""
    given = os.environ.get("WMSLICE_BIN")
    if given:
        return given
    exe = _target_dir() / "debug" / "wmslice"
    if not exe.exists():
        subprocess.run(["cargo", "build", "--quiet", "--bin", "wmslice"], cwd=REPO, check=True)
    return str(exe)


@pytest.fixture(scope="session")
def cli(wmslice_bin):
    """Runs the CLI; returns stdout bytes (raises on a non-zero exit)."""

    def run(*args: str) -> bytes:
        r = subprocess.run([wmslice_bin, *args], capture_output=True)
        assert r.returncode == 0, r.stderr.decode()
        return r.stdout

    return run


def torus(nu: int, nv: int, big=40.0, small=15.0, dtype=np.float32):
    """A torus centred at the origin (axis z), `2 nu nv` triangles, faces
    counter-clockwise seen from outside (as bench/meshgen.rs builds it,
    without the tilt)."""
    u = 2 * np.pi * (np.arange(nu) + 0.25) / nu
    v = 2 * np.pi * (np.arange(nv) + 0.5) / nv
    rr = big + small * np.cos(v)[:, None]
    x = rr * np.cos(u)[None, :]
    y = rr * np.sin(u)[None, :]
    z = np.broadcast_to(small * np.sin(v)[:, None], x.shape)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(dtype)
    j = np.arange(nv)[:, None]
    i = np.arange(nu)[None, :]
    a0 = j * nu + i
    a1 = j * nu + (i + 1) % nu
    b0 = ((j + 1) % nv) * nu + i
    b1 = ((j + 1) % nv) * nu + (i + 1) % nu
    faces = np.concatenate(
        [np.stack([a0, a1, b1], -1).reshape(-1, 3), np.stack([a0, b1, b0], -1).reshape(-1, 3)]
    )
    return vertices, faces.astype(np.int64)


def unit_cube():
    """The unit cube [0, 1]^3, 12 triangles, outward."""
    v = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float64)
    f = np.array(
        [
            [0, 2, 1], [1, 2, 3],  # bottom (z = 0), facing down
            [4, 5, 6], [5, 7, 6],  # top (z = 1), facing up
            [0, 1, 4], [1, 5, 4],  # y = 0
            [2, 6, 3], [3, 6, 7],  # y = 1
            [0, 4, 2], [2, 4, 6],  # x = 0
            [1, 3, 5], [3, 7, 5],  # x = 1
        ]
    )
    return v, f


@pytest.fixture
def scratch(tmp_path):
    yield tmp_path
    shutil.rmtree(tmp_path, ignore_errors=True)
