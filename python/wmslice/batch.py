"""Many parts, one JSON document per part, on the local cores or a dask cluster.

``slice_files(paths, out_dir, layer_height=0.2)`` slices each mesh file at
its uniform layers (and/or explicit ``levels``) and writes
``out_dir/<stem>.json`` (SPEC 9, byte-equal to ``wmslice slice PATH
--layer-height H --format json``) and, by default, its certificate
``out_dir/<stem>.cert.json`` (input and result hashes, exact per-level
counts and areas, the independent verifier's verdict), each atomically.

With a ``dask.distributed`` client, each part is one task; a part whose plan
has more than ``levels_per_task`` levels is split into shards of that many
levels, sliced as separate tasks, and joined in level order by one more
task (the shards' texts go through temporary files in ``out_dir``, not
through the scheduler). Workers must be able to read ``paths`` and write
``out_dir`` (a shared file system on a multi-machine cluster) and have
``wmslice`` installed. With ``client=None`` the parts are sliced one after
the other, each on all local cores. Nothing here schedules work itself.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Iterable

from . import _native

__all__ = ["slice_files"]


def _part(path, output, certificate, plan, exact, threads, max_levels):
    return _native.slice_part(
        path, output, certificate, exact=exact, threads=threads, max_levels=max_levels, **plan
    )


def _shard(path, output, certificate, plan, exact, threads, start, stop):
    return _native.slice_part(
        path, output, certificate, exact=exact, threads=threads, shard=(start, stop), **plan
    )


def _join(path, output, certificate, snap, exact, drop_collapsed, weld, shards):
    return _native.join_shards(path, output, shards, certificate, snap, exact, drop_collapsed, weld)


def _outputs(paths: list[str], out_dir: Path, certificate: bool) -> list[tuple[str, str | None]]:
    # Every file name written, and the part that writes it: `a/x.stl` and
    # `b/x.stl` would both write x.json; with certificates, `x.cert.stl`
    # would write x's certificate.
    seen: dict[str, str] = {}
    out = []
    for p in paths:
        stem = Path(p).stem
        names = [f"{stem}.json"] + ([f"{stem}.cert.json"] if certificate else [])
        for name in names:
            if name in seen:
                raise ValueError(f"{p} and {seen[name]} would both write {name}: rename one")
        seen.update((name, p) for name in names)
        out.append((str(out_dir / names[0]), str(out_dir / names[1]) if certificate else None))
    return out


def _result(path: str, d: dict) -> dict:
    return {
        "input": path,
        "output": d["output"],
        "certificate": d["certificate"],
        "levels": d["levels"],
        "bytes": d["bytes"],
        "sha256": d["sha256"],
        "mesh_sha256": d["mesh_sha256"],
    }


def slice_files(
    paths: Iterable[str | os.PathLike],
    out_dir: str | os.PathLike,
    layer_height: Any = None,
    *,
    first: Any = None,
    last: Any = None,
    levels: Iterable[Any] | None = None,
    snap: Any = None,
    drop_collapsed: bool = False,
    weld: bool = False,
    exact: bool = False,
    certificate: bool = True,
    client: Any = None,
    levels_per_task: int = 1000,
    threads: int | None = None,
) -> list[dict]:
    """Slices every file and writes one JSON document (and certificate) per part.

    ``layer_height``, ``first``, ``last`` and ``levels`` plan the levels as
    the command line's ``--layer-height``, ``--first``, ``--last`` and
    ``--at`` do (exact values: a float is its binary value, ``'0.2'`` is
    1/5). ``weld`` merges each mesh's vertices at exactly one point first
    (as ``--weld``; the header counts them); ``snap`` snaps each mesh to a
    grid; ``drop_collapsed`` removes
    faces that use one vertex twice instead of refusing the part (as
    ``--drop-collapsed``; the header counts them); ``exact`` adds the
    exact values to the JSON. ``threads``: workers per task (default: all cores
    locally, 1 per task on a dask cluster, whose workers run tasks side by
    side). Returns, in the order of ``paths``, a dict per part: ``input``,
    ``output``, ``certificate`` (or None), ``levels``, ``bytes``,
    ``sha256`` (of the JSON written) and ``mesh_sha256``. The first error
    (an unreadable file, an :class:`wmslice.InvalidMesh`, ...) is raised.
    """
    paths = [os.fspath(p) for p in paths]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if layer_height is None and levels is None:
        raise ValueError("no levels: give layer_height and/or levels")
    if levels_per_task < 1:
        raise ValueError("levels_per_task must be at least 1")
    plan = {
        "snap": snap,
        "drop_collapsed": drop_collapsed,
        "weld": weld,
        "layer_height": layer_height,
        "first": first,
        "last": last,
        "levels": None if levels is None else list(levels),
    }
    outs = _outputs(paths, out_dir, certificate)
    if client is None:
        return [
            _result(p, _part(p, o, c, plan, exact, threads, None))
            for p, (o, c) in zip(paths, outs)
        ]
    threads = 1 if threads is None else threads
    first_pass = [
        client.submit(_part, p, o, c, plan, exact, threads, levels_per_task, pure=False)
        for p, (o, c) in zip(paths, outs)
    ]
    done = client.gather(first_pass)
    joins = {}
    for i, (p, (o, c), d) in enumerate(zip(paths, outs, done)):
        if "split" not in d:
            continue
        n = d["split"]
        shards = []
        for start in range(0, n, levels_per_task):
            stop = min(start + levels_per_task, n)
            shard_out = str(Path(o).with_name(f".{Path(o).name}.shard-{start:09d}"))
            shards.append(
                client.submit(_shard, p, shard_out, c, plan, exact, threads, start, stop, pure=False)
            )
        joins[i] = client.submit(_join, p, o, c, snap, exact, drop_collapsed, weld, shards, pure=False)
    for i, d in zip(joins, client.gather(list(joins.values()))):
        done[i] = d
    return [_result(p, d) for p, d in zip(paths, done)]
