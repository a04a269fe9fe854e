"""Score other slicers on adversarial meshes with exact answers.

::

    python -m wmslice.probe --peer manifold3d --peer trimesh \\
        [--peer cmd:'my-slicer {mesh} {z}'] --seeds N [--families NAME ...] \\
        --json FILE [--markdown FILE]

For every family (``wmslice gen --families``) and seed ``0 .. N-1`` the
mesh is generated and its answers computed (every critical height and the
midpoints between them, each with the exact summary of its level set, re-
checked by the independent verifier). Each peer slices the mesh at each
listed level (the nearest double of the exact level; the mesh as sliced,
coordinates rounded to doubles), and the level is scored by the first of
S_O, L-, L+ whose loop count equals the peer's and whose exact total area
is within the stated bound of the peer's; else ``none``. So the counts of a
peer add up to its levels.

Peers are float and orient loops as they like, so a peer's area is taken
by nesting, not by orientation: each loop's absolute shoelace area counts
positive at even depth (inside an even number of the peer's other loops,
by the even-odd test of a point just inside it) and negative at odd depth.
Loops with fewer than three points, or whose area is within the bound, are
left out (a float peer cannot draw a loop that collapses onto a ridge);
the exact side is compared the same way: SPEC 9's totals (outer loops
positive, holes negative) and the loop counts without collapsed loops.

A ``cmd:`` peer is any program: ``{mesh}`` in its template becomes an
OFF file of the mesh (coordinates as ``repr`` of the doubles), ``{z}``
the level as a decimal double; it writes its loops to stdout as JSON, a
list of loops, each a list of ``[x, y]``. A failing run scores ``none``
and is counted under ``errors``.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
from fractions import Fraction
from typing import Callable, Iterable, Sequence

import numpy as np

import wmslice

#: A peer's area matches when within this fraction of the mesh's x-y
#: bounding-box area (floats: the bound is about rounding, not geometry).
AREA_TOLERANCE = 1e-6
TOLERANCE_NOTE = "|peer area - exact area| <= 1e-6 x the area of the mesh's x-y bounding box"

CATEGORIES = ("S_O", "L-", "L+", "none")

Loops = list  # a list of (k, 2) float arrays

# ------------------------------------------------------------------ areas


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _inside(pt: np.ndarray, poly: np.ndarray) -> bool:
    """Even-odd point-in-polygon test."""
    x, y = pt
    xs, ys = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(xs, -1), np.roll(ys, -1)
    crosses = (ys > y) != (yn > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = xs + (y - ys) * (xn - xs) / (yn - ys)
    return bool(np.count_nonzero(crosses & (x < xi)) % 2)


def _inner_point(p: np.ndarray, signed: float) -> np.ndarray:
    """A point just inside loop ``p``: off the middle of its longest edge,
    toward its interior, by a millionth of that edge. Loops that touch or
    run along each other (as limits do at ridges) then still test
    correctly, where a point on the loop would not."""
    d = np.roll(p, -1, axis=0) - p
    i = int(np.argmax(np.hypot(d[:, 0], d[:, 1])))
    left = np.array([-d[i, 1], d[i, 0]])
    inward = left if signed > 0 else -left
    return p[i] + d[i] / 2 + 1e-6 * inward


def loops_and_area(loops: Iterable[np.ndarray], negligible: float = 0.0) -> tuple[int, float]:
    """The count of a peer's loops that enclose more than ``negligible``
    area, and their nesting-signed total area (see the module
    documentation)."""
    kept = [np.asarray(p, dtype=float)[:, :2] for p in loops if len(p) >= 3]
    signed = [_signed_area(p) for p in kept]
    real = [(p, a) for p, a in zip(kept, signed) if abs(a) > negligible]
    total = 0.0
    for p, a in real:
        pt = _inner_point(p, a)
        depth = sum(1 for q, _ in real if q is not p and _inside(pt, q))
        total += abs(a) if depth % 2 == 0 else -abs(a)
    return len(real), total


# ------------------------------------------------------------------ peers


def _manifold3d(vertices: np.ndarray, faces: np.ndarray) -> Callable[[float], Loops]:
    import manifold3d as m3d

    # manifold3d's meshes are float32: the peer slices the float32 mesh.
    solid = m3d.Manifold(
        m3d.Mesh(
            vert_properties=np.ascontiguousarray(vertices, dtype=np.float32),
            tri_verts=np.ascontiguousarray(faces, dtype=np.uint32),
        )
    )
    return lambda z: list(solid.slice(z).to_polygons())


def _trimesh(vertices: np.ndarray, faces: np.ndarray) -> Callable[[float], Loops]:
    import trimesh

    tm = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)

    def at(z: float) -> Loops:
        section = tm.section(plane_origin=[0.0, 0.0, z], plane_normal=[0.0, 0.0, 1.0])
        if section is None:
            return []
        return [np.asarray(p)[:, :2] for p in section.discrete]

    return at


def _command(template: str) -> Callable[[np.ndarray, np.ndarray], Callable[[float], Loops]]:
    def make(vertices: np.ndarray, faces: np.ndarray) -> Callable[[float], Loops]:
        fd, path = tempfile.mkstemp(suffix=".off", prefix="wmslice-probe-")
        with os.fdopen(fd, "w") as f:
            f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
            for x, y, z in vertices.tolist():  # Python floats: repr round-trips
                f.write(f"{x!r} {y!r} {z!r}\n")
            for a, b, c in faces.tolist():
                f.write(f"3 {a} {b} {c}\n")

        def at(z: float) -> Loops:
            cmd = template.replace("{mesh}", shlex.quote(path)).replace("{z}", repr(z))
            out = subprocess.run(cmd, shell=True, capture_output=True, text=True, check=True)
            return [np.asarray(loop, dtype=float) for loop in json.loads(out.stdout)]

        at.cleanup = lambda: os.unlink(path)  # type: ignore[attr-defined]
        return at

    return make


def peer_factory(spec: str):
    """The peer named by ``spec``: ``manifold3d``, ``trimesh`` or ``cmd:TEMPLATE``."""
    if spec == "manifold3d":
        return _manifold3d
    if spec == "trimesh":
        return _trimesh
    if spec.startswith("cmd:"):
        return _command(spec[4:])
    raise ValueError(f"unknown peer {spec!r}: manifold3d, trimesh or cmd:TEMPLATE")


# ------------------------------------------------------------------ scoring


def score_level(answer: dict, count: int, area: float, tolerance: float) -> str:
    """The first of S_O, L-, L+ the peer's loops match at this level, or none."""
    s = answer["summary"]
    # A collapsed loop of L- or L+ has no area: no float peer draws it.
    for name, n, exact in (
        ("S_O", s["S_O_loops"], s["S_O_area"]),
        ("L-", s["L_minus_loops"] - s["L_minus_collapsed"], s["L_minus_area"]),
        ("L+", s["L_plus_loops"] - s["L_plus_collapsed"], s["L_plus_area"]),
    ):
        if count == n and abs(area - float(Fraction(exact))) <= tolerance:
            return name
    return "none"


def _empty() -> dict:
    return {c: 0 for c in CATEGORIES}


def probe(peers: Sequence[str], seeds: int, families: Sequence[str] | None = None) -> dict:
    """Runs every peer on every generated mesh at every listed level; the
    report (see the module documentation)."""
    names = [f for f, _ in wmslice.families()]
    chosen = list(families) if families else names
    for f in chosen:
        if f not in names:
            raise ValueError(f"unknown family {f!r}: {', '.join(names)}")
    makers = [(spec, peer_factory(spec)) for spec in peers]
    results = {spec: {"levels": 0, "errors": 0, "matches": _empty(), "by_kind": {}} for spec in peers}
    for family in chosen:
        for seed in range(seeds):
            mesh = wmslice.generate(family, seed)
            answers = wmslice.answers(family, seed)
            vertices, faces = mesh.vertices, mesh.faces
            span = vertices.max(axis=0) - vertices.min(axis=0)
            tolerance = AREA_TOLERANCE * float(span[0] * span[1])
            for spec, make in makers:
                r = results[spec]
                at = make(vertices, faces)
                try:
                    for answer in answers["levels"]:
                        z = float(Fraction(answer["z"]))
                        try:
                            count, area = loops_and_area(at(z), tolerance)
                            got = score_level(answer, count, area, tolerance)
                        except Exception:  # a peer that fails scores none
                            r["errors"] += 1
                            got = "none"
                        r["levels"] += 1
                        r["matches"][got] += 1
                        kind = r["by_kind"].setdefault(answer["kind"], {"levels": 0, **_empty()})
                        kind["levels"] += 1
                        kind[got] += 1
                finally:
                    getattr(at, "cleanup", lambda: None)()
    for spec in peers:
        if spec in ("manifold3d", "trimesh"):
            from importlib.metadata import version

            results[spec]["version"] = version(spec)
    return {
        "format": "wmslice-probe",
        "version": 1,
        "families": chosen,
        "seeds": seeds,
        "area_tolerance": TOLERANCE_NOTE,
        "peers": [{"peer": spec, **results[spec]} for spec in peers],
    }


def markdown(report: dict) -> str:
    """The report as markdown tables: one line per peer, then per kind."""
    lines = []
    if "command" in report:
        lines += [f"Made by `{report['command']}`.", ""]
    lines += [
        f"Families: {', '.join(report['families'])}; seeds 0..{report['seeds'] - 1}. "
        f"A level matches when the loop count is equal and {report['area_tolerance']}; "
        "each level is scored by the first of S_O, L-, L+ it matches.",
        "",
        "| peer | version | levels | S_O | L- | L+ | none | errors |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for p in report["peers"]:
        m = p["matches"]
        lines.append(f"| {p['peer']} | {p.get('version', '')} | {p['levels']} | {m['S_O']} | {m['L-']} | {m['L+']} | {m['none']} | {p['errors']} |")
    for p in report["peers"]:
        lines += ["", f"**{p['peer']}** by degeneracy kind", "", "| kind | levels | S_O | L- | L+ | none |", "|---|---:|---:|---:|---:|---:|"]
        for kind in sorted(p["by_kind"]):
            k = p["by_kind"][kind]
            lines.append(f"| {kind} | {k['levels']} | {k['S_O']} | {k['L-']} | {k['L+']} | {k['none']} |")
    return "\n".join(lines) + "\n"


def _write(path: str, text: str) -> None:
    """Writes atomically: a temporary file in the same folder, then renamed."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".wmslice-probe-")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m wmslice.probe", description=__doc__.split("\n\n")[0])
    ap.add_argument("--peer", action="append", required=True, help="manifold3d, trimesh or cmd:'TEMPLATE' (repeatable)")
    ap.add_argument("--seeds", type=int, default=3, help="seeds 0..N-1 per family (default 3)")
    ap.add_argument("--families", nargs="+", help="families to run (default: all)")
    ap.add_argument("--json", required=True, help="where to write the report")
    ap.add_argument("--markdown", help="also write the tables here")
    a = ap.parse_args(argv)
    if a.seeds < 1:
        ap.error("--seeds must be at least 1")
    report = probe(a.peer, a.seeds, a.families)
    report["command"] = " ".join(["python -m wmslice.probe", *map(shlex.quote, argv if argv is not None else sys.argv[1:])])
    _write(a.json, json.dumps(report, indent=1) + "\n")
    table = markdown(report)
    if a.markdown:
        _write(a.markdown, table)
    sys.stdout.write(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
