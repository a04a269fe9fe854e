"""Exact level sets of closed triangle meshes (weak-Morse slicing).

numpy in and out::

    import numpy as np, wmslice
    m = wmslice.Mesh(vertices, faces)          # (n, 3) float64/float32, (m, 3) integers; validated
    ls = m.slice("3/5")                        # an exact level: float (its exact binary value), int, str, Fraction
    for loop in ls.contours:                   # S_O: outer counter-clockwise, holes clockwise
        loop.points, loop.area, loop.role, loop.parent
    many = m.slice_layers(0.2)                 # uniform layers, all cores, GIL released
    many.to_json()                             # SPEC 9, byte-equal to `wmslice slice ... --format json`

Every decision is exact; points are the nearest doubles of the exact points
(``exact=True`` adds the exact values as Fractions). A mesh that is not a
closed, consistently oriented 2-manifold raises :class:`InvalidMesh` (a
``ValueError``) naming every defect by element id.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from fractions import Fraction
from typing import Any, Iterable, Iterator

from . import _native
from ._native import InternalError, InvalidMesh

__all__ = [
    "Mesh",
    "LevelSet",
    "LevelSets",
    "Loop",
    "Region",
    "Ridge",
    "Extremum",
    "Saddle",
    "InvalidMesh",
    "InternalError",
    "load",
    "dataset",
    "datasets",
    "exact_value",
    "families",
    "generate",
    "answers",
]

__version__ = _native.__version__


def exact_value(x: Any) -> Fraction:
    """The exact value the package takes for a level, layer height or snap grid.

    A float is its exact binary value (``0.1`` is not 1/10: write ``"0.1"``),
    a str goes through the exact parser (``"0.1"``, ``"3/5"``, ``"-1e-3"``),
    ints, Fractions, Decimals and numpy numbers are exact. Anything else, a
    bool, NaN or an infinity raises ``ValueError``.
    """
    return _native.exact_value(x)


class Loop:
    """A closed, oriented loop (SPEC 9's loop keys).

    ``points``: ``(k, 2)`` float64 ndarray, the nearest doubles of the exact
    points (first point not repeated). ``area``: the signed area (positive
    counter-clockwise), the nearest double of the exact area when sliced
    with ``exact=True``, else a double within a certified bound of it whose
    sign is exact. ``role``: ``'outer'`` or ``'hole'``; ``parent``: index of
    the smallest enclosing loop of the same family, or None. ``collapsed``
    (L-, L+ only): the loop has zero width in the limit (SPEC 6).
    With ``exact=True``: ``area_exact`` (Fraction), ``exact`` (list of
    ``(Fraction, Fraction)``) and ``on`` (the mesh element of each point,
    ``('edge', id)`` or ``('vertex', id)``); else these are None.
    """

    __slots__ = ("points", "area", "role", "parent", "collapsed", "_src", "_exact")

    def __init__(self, points, area, role, parent, collapsed, src=None, exact=None):
        self.points = points
        self.area = float(area)
        self.role = role
        self.parent = parent
        self.collapsed = bool(collapsed)
        self._src = src  # (native level, family, index, region) while exact values are not taken
        self._exact = exact  # (exact points, on, area_exact) once taken

    def _exact_values(self):
        if self._exact is None and self._src is not None:
            level, family, index, region = self._src
            if level.exact:
                self._exact = level.loop_exact(family, index, region)
                self._src = None
        return self._exact

    @property
    def area_exact(self) -> Fraction | None:
        e = self._exact_values()
        return None if e is None else e[2]

    @property
    def exact(self) -> list[tuple[Fraction, Fraction]] | None:
        e = self._exact_values()
        return None if e is None else e[0]

    @property
    def on(self) -> list[tuple[str, int]] | None:
        e = self._exact_values()
        return None if e is None else e[1]

    def __len__(self) -> int:
        return len(self.points)

    def __getstate__(self):
        return {
            "points": self.points,
            "area": self.area,
            "role": self.role,
            "parent": self.parent,
            "collapsed": self.collapsed,
            "exact": self._exact_values(),
        }

    def __setstate__(self, s):
        Loop.__init__(self, s["points"], s["area"], s["role"], s["parent"], s["collapsed"], None, s["exact"])

    def __repr__(self) -> str:
        extra = ", collapsed" if self.collapsed else ""
        return f"Loop({self.role}, {len(self.points)} points, area {self.area:g}, parent {self.parent}{extra})"


def _loops(level, family: str, region: int | None = None) -> list[Loop]:
    points, starts, areas, roles, parents, collapsed = level.family(family, region)
    return [
        Loop(points[starts[i] : starts[i + 1]], areas[i], roles[i], parents[i], collapsed[i], (level, family, i, region))
        for i in range(len(roles))
    ]


class Region:
    """A region F of faces lying in the plane: ``facing`` (``'up'``,
    ``'down'``, ``'flat'``), ``faces`` (uint32 ndarray of face ids,
    ascending), ``area`` (exact, a Fraction) and ``boundary`` (dF: loops in
    the direction the faces induce)."""

    __slots__ = ("facing", "faces", "area", "boundary")

    def __init__(self, facing, faces, area, boundary):
        self.facing, self.faces, self.area, self.boundary = facing, faces, area, boundary

    def __getstate__(self):
        return (self.facing, self.faces, self.area, self.boundary)

    def __setstate__(self, s):
        self.facing, self.faces, self.area, self.boundary = s

    def __repr__(self) -> str:
        return f"Region({self.facing}, {len(self.faces)} faces, area {self.area}, {len(self.boundary)} boundary loops)"


class Ridge:
    """A ridge or valley polyline S_NO lying in the plane: ``kind``
    (``'ridge'`` or ``'valley'``), ``closed``, ``vertices`` (uint32 ndarray)
    and ``points`` (``(k, 2)`` float64, nearest doubles)."""

    __slots__ = ("kind", "closed", "vertices", "points")

    def __init__(self, kind, closed, vertices, points):
        self.kind, self.closed, self.vertices, self.points = kind, closed, vertices, points

    def __getstate__(self):
        return (self.kind, self.closed, self.vertices, self.points)

    def __setstate__(self, s):
        self.kind, self.closed, self.vertices, self.points = s

    def __repr__(self) -> str:
        return f"Ridge({self.kind}, {'closed' if self.closed else 'open'}, {len(self.vertices)} vertices)"


class Extremum:
    """An isolated extremal vertex P on the plane: ``vertex``, ``kind``
    (``'min'`` or ``'max'``) and ``point`` (``(x, y)``, nearest doubles)."""

    __slots__ = ("vertex", "kind", "point")

    def __init__(self, vertex, kind, point):
        self.vertex, self.kind, self.point = vertex, kind, point

    def __getstate__(self):
        return (self.vertex, self.kind, self.point)

    def __setstate__(self, s):
        self.vertex, self.kind, self.point = s

    def __repr__(self) -> str:
        return f"Extremum({self.kind} at vertex {self.vertex})"


class Saddle:
    """A saddle vertex with ``branches`` = 2m S_O branches (``m`` = 2: an
    ordinary saddle, 3: a monkey saddle)."""

    __slots__ = ("vertex", "branches")

    def __init__(self, vertex, branches):
        self.vertex, self.branches = vertex, branches

    @property
    def m(self) -> int:
        return self.branches // 2

    def __getstate__(self):
        return (self.vertex, self.branches)

    def __setstate__(self, s):
        self.vertex, self.branches = s

    def __repr__(self) -> str:
        return f"Saddle(vertex {self.vertex}, {self.branches} branches)"


def _json_arguments(exact, path):
    """``to_json``'s arguments, a path given first taken for the path
    (``to_json("out.json")``): a bool is never a path."""
    if path is None and isinstance(exact, (str, bytes, os.PathLike)):
        return None, exact
    return exact, path


class LevelSet:
    """The complete level set of a mesh at one exact level ``z`` (SPEC 3-6).

    ``contours`` (S_O), ``below`` (L-) and ``above`` (L+) are lists of
    :class:`Loop`; ``faces`` of :class:`Region`; ``ridges`` of
    :class:`Ridge`; ``points`` of :class:`Extremum`; ``saddles`` of
    :class:`Saddle`. Each list is made on first access (the points were
    rounded on the slicing threads) and kept. Pickles exactly.
    """

    __slots__ = ("_level", "_cache")

    def __init__(self, native):
        self._level = native
        self._cache = {}

    @property
    def z(self) -> Fraction:
        """The exact level."""
        return self._level.z

    @property
    def exact(self) -> bool:
        """Whether it was sliced with ``exact=True``."""
        return self._level.exact

    def _get(self, key, make):
        v = self._cache.get(key)
        if v is None:
            v = self._cache[key] = make()
        return v

    @property
    def contours(self) -> list[Loop]:
        """S_O: oriented contours, material on the left."""
        return self._get("contours", lambda: _loops(self._level, "contours"))

    @property
    def below(self) -> list[Loop]:
        """L-: the regular contour just below the level."""
        if self._level.shared():
            return list(self.contours)
        return self._get("below", lambda: _loops(self._level, "below"))

    @property
    def above(self) -> list[Loop]:
        """L+: the regular contour just above the level."""
        if self._level.shared():
            return list(self.contours)
        return self._get("above", lambda: _loops(self._level, "above"))

    @property
    def faces(self) -> list[Region]:
        """F: regions of faces lying in the plane, with their boundaries dF."""

        def make():
            return [
                Region(facing, faces, area, _loops(self._level, "boundary", i))
                for i, (facing, faces, area) in enumerate(self._level.regions())
            ]

        return self._get("faces", make)

    @property
    def ridges(self) -> list[Ridge]:
        """S_NO: ridge and valley polylines lying in the plane."""
        return self._get("ridges", lambda: [Ridge(*r) for r in self._level.ridges()])

    @property
    def points(self) -> list[Extremum]:
        """P: isolated minima and maxima on the plane."""
        return self._get("points", lambda: [Extremum(v, k, (x, y)) for v, k, x, y in self._level.extrema()])

    @property
    def saddles(self) -> list[Saddle]:
        """Vertices with 2m >= 4 contour branches."""
        return self._get("saddles", lambda: [Saddle(v, b) for v, b in self._level.saddles()])

    def to_json(self, exact: bool | None = None, path=None) -> str | None:
        """The SPEC 9 document of this level alone (header included),
        byte-equal to ``wmslice slice MESH --at Z --format json [--exact]``;
        ``exact`` defaults to how the level was sliced. With ``path``, the
        document is written there atomically instead (``to_json(path)``
        works too)."""
        exact, path = _json_arguments(exact, path)
        return _native.document([self._level], exact, path)

    def to_shapely(self, family: str = "contours"):
        """The region enclosed by a family (``contours``, ``below`` or
        ``above``) as a shapely ``MultiPolygon``: each outer loop with the
        holes whose parent it is (collapsed loops, of zero area, are left
        out). Needs shapely >= 2."""
        try:
            import shapely
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("LevelSet.to_shapely needs shapely (pip install 'wmslice[shapely]')") from e
        loops = getattr(self, family)
        holes: dict[int, list] = {}
        for lp in loops:
            if lp.role == "hole" and lp.parent is not None and not lp.collapsed:
                holes.setdefault(lp.parent, []).append(lp.points)
        polygons = [
            shapely.Polygon(lp.points, holes.get(i, []))
            for i, lp in enumerate(loops)
            if lp.role == "outer" and not lp.collapsed
        ]
        return shapely.MultiPolygon(polygons)

    def __reduce__(self):
        return (LevelSet, (self._level,))

    def __repr__(self) -> str:
        parts = [f"{len(self.contours)} contours"]
        for name in ("faces", "ridges", "points", "saddles"):
            n = len(getattr(self, name))
            if n:
                parts.append(f"{n} {name}")
        return f"LevelSet(z={self.z}, {', '.join(parts)})"


class LevelSets(Sequence):
    """The level sets of many levels, ascending; a list-like of
    :class:`LevelSet` with :meth:`to_json` for all of them."""

    __slots__ = ("_sets",)

    def __init__(self, sets: Iterable[LevelSet]):
        self._sets = list(sets)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return LevelSets(self._sets[i])
        return self._sets[i]

    def __len__(self) -> int:
        return len(self._sets)

    def __iter__(self) -> Iterator[LevelSet]:
        return iter(self._sets)

    @property
    def levels(self) -> list[Fraction]:
        """The exact levels."""
        return [s.z for s in self._sets]

    def to_json(self, exact: bool | None = None, path=None) -> str | None:
        """One SPEC 9 document of every level, byte-equal to the command
        line's for the same mesh and levels (texts made in parallel,
        without the GIL). ``exact`` defaults to how the levels were sliced;
        with ``path`` the document is written there atomically
        (``to_json(path)`` works too)."""
        exact, path = _json_arguments(exact, path)
        return _native.document([s._level for s in self._sets], exact, path)

    def __reduce__(self):
        return (LevelSets, (self._sets,))

    def __repr__(self) -> str:
        if not self._sets:
            return "LevelSets([])"
        return f"LevelSets({len(self._sets)} levels, z {self._sets[0].z} .. {self._sets[-1].z})"


class Mesh:
    """A closed, consistently oriented triangle mesh, validated and ready to
    slice.

    ``Mesh(vertices, faces, snap=None, drop_collapsed=False, weld=False)``:
    ``vertices`` ``(n, 3)`` float64 or float32 (taken exactly), ``faces``
    ``(m, 3)`` of any integer type, counter-clockwise seen from outside.
    With ``weld``, vertices at exactly one point (equal coordinates: an
    exporter's seams) are merged first, as ``--weld`` does (exact, nothing
    moves; vertices renumbered in first-seen order; :attr:`welded` counts
    them). With ``snap`` (a grid step such as ``'1/10000'``), every coordinate
    moves to the nearest multiple (the one reported rounding). With
    ``drop_collapsed``, faces that use one vertex twice (no area) are
    removed instead of refused, as ``--drop-collapsed`` does (later faces
    are renumbered; :attr:`dropped` lists them). Degenerate faces are
    removed by edge flips, as the command line does, then the mesh is
    validated: :class:`InvalidMesh` names every defect (open edges, NaN
    coordinates, ...).
    """

    __slots__ = ("_m",)

    def __init__(self, vertices, faces, snap=None, drop_collapsed: bool = False, weld: bool = False):
        self._m = _native.Mesh(vertices, faces, snap, drop_collapsed, weld)

    @classmethod
    def _wrap(cls, native) -> "Mesh":
        m = cls.__new__(cls)
        m._m = native
        return m

    @classmethod
    def from_trimesh(cls, t, snap=None, drop_collapsed: bool = False, weld: bool = False) -> "Mesh":
        """From a ``trimesh.Trimesh`` (its vertices and faces as they are;
        trimesh merges vertices on load unless told not to: with
        ``process=False``, give ``weld=True``)."""
        return cls(t.vertices, t.faces, snap, drop_collapsed, weld)

    vertices = property(lambda self: self._m.vertices, doc="(n, 3) float64 vertices as sliced.")
    faces = property(lambda self: self._m.faces, doc="(m, 3) uint32 faces as sliced (after flips).")
    num_vertices = property(lambda self: self._m.num_vertices)
    num_faces = property(lambda self: self._m.num_faces)
    snap = property(lambda self: self._m.snap, doc="The snap grid as 'p/q', or None.")
    snap_report = property(lambda self: self._m.snap_report, doc="What snapping did, or None.")
    flips = property(lambda self: self._m.flips, doc="The edge flips that removed degenerate faces.")
    dropped = property(
        lambda self: self._m.dropped,
        doc="The faces drop_collapsed removed (ids as given), or None when not asked for.",
    )
    welded = property(
        lambda self: self._m.welded,
        doc="How many vertices weld merged into an earlier one at the same point, or None when not asked for.",
    )
    sha256 = property(lambda self: self._m.sha256, doc="SHA-256 of the mesh as sliced (the JSON header's).")
    z_range = property(lambda self: self._m.z_range, doc="Exact (z_min, z_max) as Fractions.")

    def slice(self, z, exact: bool = False) -> LevelSet:
        """The level set at the exact level ``z`` (float: its exact binary
        value; int; str such as ``'3/5'`` or ``'0.6'``; Fraction)."""
        return LevelSet(self._m.slice(z, exact))

    def slice_many(self, levels, exact: bool = False, threads: int | None = None) -> LevelSets:
        """The level sets at many levels (a numpy array or any iterable of
        exact values), sliced and returned ascending and distinct, as the
        command line does, by a plane sweep on ``threads`` workers (default:
        all cores) with the GIL released; the result does not depend on
        ``threads``."""
        return LevelSets(LevelSet(x) for x in self._m.slice_many(levels, exact, threads))

    def layer_levels(self, layer_height, first=None, last=None) -> list[Fraction]:
        """The exact uniform levels ``first + k * layer_height <= last``
        (defaults: mid-layer above the lowest vertex; the highest vertex)."""
        return self._m.layer_levels(layer_height, first, last)

    def slice_layers(self, layer_height, first=None, last=None, exact: bool = False, threads: int | None = None) -> LevelSets:
        """:meth:`slice_many` at :meth:`layer_levels` (the command line's
        ``--layer-height``, ``--first``, ``--last``)."""
        return LevelSets(LevelSet(x) for x in self._m.slice_layers(layer_height, first, last, exact, threads))

    def critical(self, layer_height=None, fit: bool = False, first=None) -> dict:
        """The critical heights and the unperturbed Reeb graph, as the
        ``wmslice-critical`` document of ``wmslice critical --format json``
        (a dict; heights are exact ``'p/q'`` strings). With ``layer_height``:
        ``fit=True`` adds the fitted plan (``'layers'``: each between H/2 and
        3H/2 thick, every flat on a boundary; ``ValueError`` when two flats
        are closer than H/2), else the uniform plan's ``'audit'`` (planes
        ``first + k * layer_height``, default mid-layer above the lowest
        vertex); both add ``'clusters'`` of critical heights closer than H."""
        import json

        return json.loads(self._m.critical_json(layer_height, fit, first))

    def __reduce__(self):
        return (Mesh._wrap, (self._m,))

    def __repr__(self) -> str:
        s = f", snap {self.snap}" if self.snap else ""
        return f"Mesh({self.num_vertices} vertices, {self.num_faces} faces{s})"


def load(path, snap=None, drop_collapsed: bool = False, weld: bool = False) -> Mesh:
    """Reads a mesh file (STL binary/ASCII, OBJ, OFF, PLY, 3MF: every format
    the command line reads), merges its vertices at exactly one point when
    ``weld``, snaps it to ``snap`` when given, removes the
    faces that use one vertex twice when ``drop_collapsed`` (see
    :class:`Mesh`), removes degenerate faces and validates it. ``path`` may
    also be the file's bytes (``bytes``, ``bytearray``, ``memoryview``) or
    an open binary file; their format is told by content. ``OSError`` when the file cannot be
    read, ``ValueError`` when it cannot be parsed, :class:`InvalidMesh` when
    it is not accepted. A 3MF vertex whose transformed position is not a
    double (an object a slicer placed on its bed) has no exact place
    without a grid: ``ValueError``; with ``snap`` it is snapped from its
    exact image."""
    if hasattr(path, "read"):
        path = path.read()
        if isinstance(path, str):
            raise TypeError("load: the file is open in text mode; open it with 'rb'")
    if isinstance(path, (bytes, bytearray, memoryview)):
        return Mesh._wrap(_native.load_bytes(bytes(path), snap, drop_collapsed, weld))
    return Mesh._wrap(_native.load(path, snap, drop_collapsed, weld))


def dataset(name: str, snap=None) -> Mesh:
    """A built-in dataset (the paper's meshes, built exactly): see
    :func:`datasets`."""
    return Mesh._wrap(_native.dataset(name, snap))


def datasets() -> list[tuple[str, str, list[Fraction]]]:
    """The built-in datasets: ``(name, summary, degenerate levels)``."""
    return _native.datasets()


from . import batch  # noqa: E402  (needs the names above)


def families() -> list[tuple[str, str]]:
    """The random adversarial families (``wmslice gen --families``): ``(name, what it exercises)``."""
    return _native.family_names()


def generate(family: str, seed: int) -> Mesh:
    """The mesh of ``family`` for ``seed`` (deterministic), as its answers slice it
    (snapped to the family's grid when it has one)."""
    return Mesh._wrap(_native.family_mesh(family, seed))


def answers(family: str, seed: int) -> dict:
    """The exact answers for :func:`generate` (``wmslice gen --random SEED --family NAME
    --answers FILE`` as a dict): every critical height and the midpoint between
    consecutive ones, each with ``z`` (``'p/q'``), ``kind`` and its ``summary``."""
    import json

    return json.loads(_native.family_answers(family, seed))
