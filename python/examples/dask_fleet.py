"""A fleet of logs through pendtilt with Dask: one row of results per log, one Parquet table.

Every log (CSV or Parquet) in a directory is estimated by ``pendtilt.estimate`` on a Dask
worker; the rig file ``NAME.rig.toml`` (and, for a 3-D log, ``NAME.scenario.toml``) beside
``NAME.csv`` is used when present, as ``pendtilt simulate`` writes them. The table has a
row per log: its name, model (planar or 3d), rows, the warnings count (the ``warning:``
lines ``pendtilt estimate`` prints), and per estimator its RMS error in radians where the
log has the truth (planar: against ``theta``; 3-D: the inclination error), NaN otherwise.

On this machine (a LocalCluster of processes)::

    python dask_fleet.py LOG_DIR -o fleet.parquet --workers 4

On a cluster: start ``dask-scheduler`` on one machine and ``dask-worker tcp://HOST:8786``
on each of the others (each with ``pip install ./python`` done and the logs at the same
path, e.g. a shared file system), then::

    python dask_fleet.py LOG_DIR -o fleet.parquet --scheduler tcp://HOST:8786

The estimate releases the GIL: threads of one worker run logs in parallel too.
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any, Dict, List, Optional

import pendtilt


def logs_in(directory: Path) -> List[Path]:
    """The logs of a directory: every ``*.csv`` and ``*.parquet`` but the rig and
    estimate outputs, by name."""
    found = [p for p in directory.iterdir() if p.suffix.lower() in (".csv", ".parquet")]
    return sorted(p for p in found if not p.name.endswith((".est.csv", ".rig.csv")))


def is_3d(log: Path) -> bool:
    """Whether a log has the 3-D columns (MODEL.md 7.6): its header has ``phi_x``."""
    if log.suffix.lower() == ".parquet":
        import pyarrow.parquet as pq

        return "phi_x" in pq.read_schema(log).names
    with open(log, encoding="utf-8", errors="replace") as f:
        header = next((l for l in f if l.strip() and not l.lstrip().startswith("#")), "")
    return "phi_x" in [h.strip().strip('"') for h in header.split(",")]


def summarise(log: str) -> Dict[str, Any]:
    """One log's row: estimated with the rig file beside it (and for a 3-D log the
    scenario file, whose sensor noise figures ekf3d and ukf3d take)."""
    p = Path(log)
    rig = p.with_name(p.stem + ".rig.toml")
    scenario = p.with_name(p.stem + ".scenario.toml")
    est = pendtilt.estimate(
        p,
        rig=rig if rig.exists() else None,
        scenario=scenario if scenario.exists() and is_3d(p) else None,
    )
    row: Dict[str, Any] = {
        "log": p.name,
        "model": est.model,
        "rows": est.rows,
        "warnings": len(est.warnings),
    }
    for name in est.names:
        row[f"rms_{name}"] = est.rms.get(name, math.nan)
    return row


def run(
    directory: Path,
    output: Path,
    scheduler: Optional[str] = None,
    workers: int = 2,
    threads_per_worker: int = 1,
) -> Any:
    """Maps :func:`summarise` over the logs of ``directory`` on a Dask cluster (the
    scheduler at ``scheduler``, else a LocalCluster of ``workers`` processes) and writes
    the rows to ``output`` (Parquet). Returns the table (a pandas DataFrame)."""
    import pandas as pd
    from dask.distributed import Client, LocalCluster

    logs = [str(p) for p in logs_in(directory)]
    if scheduler is None:
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=threads_per_worker, processes=True,
            dashboard_address=None,
        )
        client = Client(cluster)
    else:
        cluster, client = None, Client(scheduler)
    try:
        rows = client.gather(client.map(summarise, logs, pure=False))
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    table = pd.DataFrame(rows)
    # Estimator columns in a fixed order: planar before 3-D, as the catalogue lists them.
    order = [f"rms_{n}" for n in pendtilt.ESTIMATORS if f"rms_{n}" in table.columns]
    table = table[["log", "model", "rows", "warnings", *order]]
    table.to_parquet(output, engine="pyarrow", index=False)
    return table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", type=Path, help="directory of logs (CSV or Parquet)")
    ap.add_argument("-o", "--output", type=Path, default=Path("fleet.parquet"),
                    help="the Parquet table to write (default fleet.parquet)")
    ap.add_argument("--scheduler", help="a running scheduler, tcp://HOST:8786 "
                    "(default: none, a LocalCluster on this machine)")
    ap.add_argument("--workers", type=int, default=2,
                    help="LocalCluster worker processes (default 2)")
    ap.add_argument("--threads", type=int, default=1,
                    help="threads per LocalCluster worker (default 1)")
    a = ap.parse_args()
    start = time.perf_counter()
    table = run(a.logs, a.output, a.scheduler, a.workers, a.threads)
    print(table.to_string(max_cols=8))
    print(f"{len(table)} logs -> {a.output} in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    main()
