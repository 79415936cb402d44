"""Campaigns under Dask (or any scheduler that ships a pickled session):
the CLI's shard rule, one shard into Parquet parts, a whole campaign mapped
over a client, and the merge check. Every rule comes from the library
(``enginedyn._native``): ``shards`` is ``batch --shard``'s, ``run_shard``
writes what ``batch --shard I/N --parquet DIR`` writes, ``check_campaign``
is ``enginedyn merge``.

>>> from dask.distributed import Client, LocalCluster       # doctest: +SKIP
>>> client = Client(LocalCluster(n_workers=2, threads_per_worker=1))
>>> manifest = map_campaign(client, session, paths, "out/", files_per_task=50)
"""

from __future__ import annotations

import json
import math
import os
from typing import Any, Dict, List, Optional, Sequence

from . import _native

__all__ = ["shards", "run_shard", "map_campaign", "check_campaign"]


def shards(paths: Sequence[Any], n: int) -> List[List[str]]:
    """The ``n`` shards of ``paths`` by the CLI's rule: sorted bytewise,
    path k to shard k mod n."""
    items = [os.fspath(p) for p in paths]
    return [[os.fspath(p) for p in _native.shard(items, i, n)] for i in range(n)]


def run_shard(
    session: Any,
    paths: Sequence[Any],
    out: Any,
    part: int,
    parts: int,
    traces: bool = False,
    overwrite: bool = False,
) -> Dict[str, Any]:
    """Shard ``part`` of ``parts`` of ``paths`` into Parquet parts in ``out``
    (one thread: the scheduler gives the parallelism). Failed files are
    error rows; returns the counts. The parts record the whole list
    (``paths``), so that ``check_campaign`` knows every file once."""
    _native.shard([], part, parts)  # the library's check of part/parts, and its message
    list_blake3, mine = _native.list_plan([os.fspath(p) for p in paths], parts)
    return _run_part(
        session, [os.fspath(p) for p in mine[part]], os.fspath(out), part, parts, list_blake3, traces, overwrite
    )


def map_campaign(
    client: Any,
    session: Any,
    paths: Sequence[Any],
    out: Any,
    files_per_task: int = 500,
    traces: bool = False,
    overwrite: bool = False,
) -> Dict[str, Any]:
    """The whole campaign over a Dask ``client``: ceil(len/files_per_task)
    shards, one task each (the session pickled to the workers), then the
    merge check; returns the manifest (``_manifest.json``). A folder that
    holds another campaign's parts is refused before any work, naming
    both; ``overwrite=True`` removes enginedyn's own parts there first."""
    items = [os.fspath(p) for p in paths]
    parts = max(1, math.ceil(len(items) / max(1, files_per_task)))
    session._full.plan_campaign(os.fspath(out), items, parts, traces, overwrite)
    # Every file's identity taken once, here: each task gets its own files
    # and the list's hash, not the whole list to canonicalise again.
    list_blake3, mine = _native.list_plan(items, parts)
    futures = [
        client.submit(_run_part, session, [os.fspath(p) for p in mine[i]], os.fspath(out), i, parts, list_blake3, traces, pure=False)
        for i in range(parts)
    ]
    client.gather(futures)
    return check_campaign(out, parts)


def _run_part(
    session: Any,
    mine: List[str],
    out: str,
    part: int,
    parts: int,
    list_blake3: str,
    traces: bool,
    overwrite: bool = False,
) -> Dict[str, Any]:
    """One part: its own files, the whole list known by its hash
    (``run_shard``, and each task of ``map_campaign``)."""
    b = session.batch(mine, jobs=1)
    written = [
        os.fspath(p)
        for p in b._native.write_parquet(out, part, parts, traces, None, overwrite, list_blake3)
    ]
    return {
        "part": part,
        "files": len(mine),
        "failed": sum(1 for e in b.errors if e is not None),
        "written": written,
    }


def check_campaign(out: Any, parts: Optional[int] = None) -> Dict[str, Any]:
    """``enginedyn merge``: every part of every table there with one schema;
    writes and returns ``_manifest.json``. A missing or different part
    raises ``DiagramError`` naming it."""
    return json.loads(_native.merge(os.fspath(out), parts))
