"""Batches of scans: smooth, take the residual, compute the areal parameters, one row per scan.

``run`` maps ``process_scan`` over a folder or a list of scan files, either in a plain
loop in this process or on a ``dask.distributed`` cluster (a ``LocalCluster`` on this
machine or a real one: the code is the same), and collects a ``pandas.DataFrame``
(optionally written as Parquet). The numbers are the same either way: every scan is
processed by the same deterministic functions, wherever it runs.

    >>> from dask.distributed import Client, LocalCluster
    >>> import beltrami.batch
    >>> with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
    ...     table = beltrami.batch.run("scans/", client=client,
    ...                                smooth={"method": "taubin", "iterations": 50},
    ...                                residual={"remove_mean": True})

The workers read the files themselves, so on a real cluster the paths must name the
same files on every worker (a shared file system). Weight schemes registered with
``beltrami.register_weight`` live in the process that registered them: register them on
the workers too (``client.run(beltrami.register_weight, name, fn)``) before using the
name in ``smooth``.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Any, Optional, Union

import beltrami as bt

__all__ = ["SUFFIXES", "process_scan", "run", "scans_in"]

#: The file extensions ``scans_in`` takes from a folder (the formats ``beltrami.read`` reads).
SUFFIXES = (".ply", ".stl", ".obj", ".off", ".x3p", ".sdf")

#: The residual's keys that are no areal parameter of the scan (options, nested parts).
_NOT_PARAMETERS = {"heights", "measured", "smoothed", "form", "smr", "smc", "spatial", "scalars"}


def scans_in(folder: Union[str, os.PathLike[str]]) -> list[str]:
    """The scan files directly in ``folder`` (extensions ``SUFFIXES``, any case), sorted by name.

    Raises ``FileNotFoundError`` when ``folder`` does not exist, ``NotADirectoryError``
    when it is not a directory and ``ValueError`` when it holds no scan.
    """
    folder = os.fspath(folder)
    if not os.path.exists(folder):
        raise FileNotFoundError(f"{folder}: no such directory")
    if not os.path.isdir(folder):
        raise NotADirectoryError(f"{folder}: not a directory")
    names = sorted(
        name
        for name in os.listdir(folder)
        if name.lower().endswith(SUFFIXES) and os.path.isfile(os.path.join(folder, name))
    )
    if not names:
        raise ValueError(f"{folder}: no scan files ({', '.join(SUFFIXES)})")
    return [os.path.join(folder, name) for name in names]


def process_scan(
    path: Union[str, os.PathLike[str]],
    smooth: Optional[Mapping[str, Any]] = None,
    residual: Optional[Mapping[str, Any]] = None,
    read: Optional[Mapping[str, Any]] = None,
) -> dict[str, Any]:
    """One scan: ``read`` it, ``smooth`` it, take the ``residual`` of the scan against
    its smoothed version, and return one flat row.

    ``smooth``, ``residual`` and ``read`` are keyword arguments of ``beltrami.smooth``,
    ``beltrami.residual`` and ``beltrami.read`` (the command line's options, same
    defaults). The row holds ``scan`` (the path), ``vertices``, ``faces``, ``stop`` and
    ``iterations`` (of the smoothing run), and every number of the
    residual's report (``sa``, ``sq``, ``sz``, ``sp``, ``sv``, ``ssk``, ``sku``,
    ``sdq``, ``sdr``, ``smr1``…, in the mesh's length unit, areas in length², ratios in
    percent), under the same keys as ``beltrami residual --json``. No timings: the row
    depends on the scan and the options only, wherever it is computed.

    Raises what ``read``, ``smooth`` and ``residual`` raise (``FormatError``,
    ``MeshError``, ``SmoothError``, ``ValueError``, ``OSError``).
    """
    mesh = bt.read(path, **dict(read or {}))
    smoothed, report = bt.smooth(mesh, **dict(smooth or {}))
    result = bt.residual(mesh, smoothed, **dict(residual or {}))
    row: dict[str, Any] = {
        "scan": os.fspath(path),
        "vertices": mesh.n_vertices,
        "faces": mesh.n_faces,
        "stop": report["stop"],
        "iterations": report["iterations"],
    }
    for key, value in result.items():
        if key in _NOT_PARAMETERS or isinstance(value, bool):
            continue
        if isinstance(value, (int, float)) or value is None:
            row[key] = value
    return row


def run(
    scans: Union[str, os.PathLike[str], Iterable[Union[str, os.PathLike[str]]]],
    *,
    client: Any = None,
    smooth: Optional[Mapping[str, Any]] = None,
    residual: Optional[Mapping[str, Any]] = None,
    read: Optional[Mapping[str, Any]] = None,
    parquet: Union[str, os.PathLike[str], None] = None,
) -> Any:
    """``process_scan`` over every scan, one row per scan in the order given, as a
    ``pandas.DataFrame``.

    ``scans`` is a folder (its ``scans_in``) or an iterable of paths. Without
    ``client`` the scans run one after the other in this process; with a
    ``dask.distributed.Client`` they are mapped over its workers (one task per scan;
    each worker needs the memory of one scan per thread, see docs/python.md) and
    gathered. A failing scan raises its error here (the other tasks are cancelled).
    With ``parquet``, the table is also written there (``DataFrame.to_parquet``, which
    needs pyarrow or fastparquet, checked before any scan runs: ``ImportError``
    without either). Needs pandas.
    """
    import importlib.util

    import pandas

    if parquet is not None and not any(
        importlib.util.find_spec(engine) for engine in ("pyarrow", "fastparquet")
    ):
        raise ImportError(
            "parquet= needs pyarrow or fastparquet (pip install pyarrow); no scan was run"
        )

    if isinstance(scans, (str, os.PathLike)):
        paths = scans_in(scans)
    else:
        paths = [os.fspath(p) for p in scans]
    options = {"smooth": smooth, "residual": residual, "read": read}
    if client is None:
        rows = [process_scan(p, **options) for p in paths]
    else:
        futures = client.map(
            process_scan,
            paths,
            key=[f"beltrami-scan-{i}-{os.path.basename(p)}" for i, p in enumerate(paths)],
            **options,
        )
        try:
            rows = client.gather(futures)
        finally:
            client.cancel(futures)
    table = pandas.DataFrame(rows)
    if parquet is not None:
        table.to_parquet(parquet, index=False)
    return table
