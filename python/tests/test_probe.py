"""The probe (``python -m wmslice.probe``) and the families from Python.

The probe's bookkeeping is checked with ``cmd:`` peers whose answers are
known: one that writes the exact slicer's S_O loops must match S_O (or
an equal L-/L+) at every level, one that writes L- must match at every
level, and one that writes nothing matches only where the answer has no
loops. manifold3d and trimesh are run to show the counts add up.
"""

import json
import sys

import pytest

import wmslice
from wmslice import probe

SCRIPT = (
    "import sys, json, wmslice; m = wmslice.load(sys.argv[1]); "
    "ls = m.slice(float(sys.argv[2])); "
    "print(json.dumps([l.points.tolist() for l in getattr(ls, sys.argv[3])]))"
)


def cmd_peer(side: str) -> str:
    return f"cmd:{sys.executable} -c '{SCRIPT}' {{mesh}} {{z}} {side}"


def test_families_are_deterministic_and_answered():
    names = [n for n, _ in wmslice.families()]
    assert len(names) >= 5
    a = wmslice.generate("height_field", 3)
    b = wmslice.generate("height_field", 3)
    assert a.sha256 == b.sha256
    ans = wmslice.answers("height_field", 3)
    assert ans["format"] == "wmslice-answers"
    assert ans["mesh"]["sha256"] == a.sha256
    crit = [l for l in ans["levels"] if l["critical"]]
    # The answers list exactly the critical heights the analysis finds.
    assert [l["z"] for l in crit] == [l["z"] for l in a.critical()["critical"]]


def test_exact_peers_match_everywhere_and_counts_add_up():
    report = probe.probe([cmd_peer("contours"), cmd_peer("below"), "cmd:echo []"], 1, ["height_field"])
    levels = len(wmslice.answers("height_field", 0)["levels"])
    exact_so, exact_below, empty = report["peers"]
    for p in report["peers"]:
        assert p["levels"] == levels
        assert sum(p["matches"].values()) == levels
        assert sum(k["levels"] for k in p["by_kind"].values()) == levels
    assert exact_so["errors"] == 0 and exact_so["matches"]["none"] == 0
    assert exact_below["errors"] == 0 and exact_below["matches"]["none"] == 0
    assert exact_below["matches"]["L-"] > 0, "L- differs from S_O at some level"
    # An empty answer matches only levels where S_O (or a limit) is empty:
    # the lowest and highest critical heights of a closed part.
    assert 0 < empty["matches"]["S_O"] + empty["matches"]["L-"] + empty["matches"]["L+"] < levels


def test_manifold3d_and_trimesh_are_scored(tmp_path):
    pytest.importorskip("manifold3d")
    pytest.importorskip("trimesh")
    out = tmp_path / "peers.json"
    md = tmp_path / "peers.md"
    assert probe.main(["--peer", "manifold3d", "--peer", "trimesh", "--seeds", "1",
                       "--families", "polycube", "--json", str(out), "--markdown", str(md)]) == 0
    report = json.loads(out.read_text())
    assert [p["peer"] for p in report["peers"]] == ["manifold3d", "trimesh"]
    for p in report["peers"]:
        assert sum(p["matches"].values()) == p["levels"] > 0
    assert "| manifold3d |" in md.read_text()
