"""The Dask fleet example over 20 simulated logs equals pendtilt estimate on each."""
import importlib.util
import math
import time
from pathlib import Path

import numpy as np
import pandas as pd

import pendtilt

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "dask_fleet.py"


def load_example():
    spec = importlib.util.spec_from_file_location("dask_fleet", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_fleet_table_equals_the_commands_results(cli, tmp_path):
    logs = tmp_path / "logs"
    logs.mkdir()
    # 16 planar rides (4 of them as Parquet) and 4 3-D rides, 10 s each.
    for k in range(16):
        sim = pendtilt.simulate("scooter", logs / f"ride{k:02}.csv", duration=10, seed=k + 1)
        if k % 4 == 3:
            sim.to_pandas().to_parquet(logs / f"ride{k:02}.parquet")
            sim.log.unlink()
            sim.log.with_name(f"ride{k:02}.rig.toml").rename(logs / f"ride{k:02}.rig.toml")
    for k in range(4):
        pendtilt.simulate("scooter3d", logs / f"sc{k}.csv", duration=10, seed=k + 1)
    fleet = load_example()
    start = time.perf_counter()
    table = fleet.run(logs, tmp_path / "fleet.parquet", workers=2, threads_per_worker=1)
    print(f"dask fleet: {len(table)} logs in {time.perf_counter() - start:.1f} s")
    back = pd.read_parquet(tmp_path / "fleet.parquet")
    pd.testing.assert_frame_equal(back, table)
    assert len(back) == 20 and sorted(back["model"].unique()) == ["3d", "planar"]

    for row in back.itertuples(index=False):
        stem = Path(row.log).stem
        log = logs / row.log
        if log.suffix == ".parquet":  # the command reads CSV: the same numbers, exactly
            log = tmp_path / f"{stem}.csv"
            pendtilt.write_csv(pd.read_parquet(logs / row.log), log)
        args = ["--params", logs / f"{stem}.rig.toml"]
        if row.model == "3d":
            args += ["--scenario", logs / f"{stem}.scenario.toml"]
        out = tmp_path / f"{stem}.est.csv"
        p = cli("estimate", log, "-o", out, *args)
        assert row.warnings == sum(l.startswith("warning:") for l in p.stderr.splitlines())
        est = pendtilt.read_csv(out)
        assert row.rows == len(est["t"])
        if row.model == "planar":
            names = [c for c in est if c not in ("t", "theta")]
            t = est["t"]
            for n in names:
                e = est[n] - est["theta"]
                ok = np.isfinite(e) & (t >= t[0] + 5.0)  # scored from 5 s on
                # Summed in row order, as the command sums.
                assert getattr(row, f"rms_{n}") == math.sqrt(np.cumsum(e[ok] ** 2)[-1] / ok.sum())
        else:
            names = [c[: -len("_roll")] for c in est if c.endswith("_roll")]
            # The command's score table: RMS in degrees, 5 decimals.
            printed = {l.split()[0]: l.split()[1] for l in p.stdout.splitlines()[2:] if l.strip()}
            for n in names:
                assert f"{math.degrees(getattr(row, f'rms_{n}')):.5f}" == printed[n], n
        # Every other estimator column of the row is NaN (the other model's).
        others = [c for c in back.columns if c.startswith("rms_") and c[4:] not in names]
        assert all(math.isnan(getattr(row, c)) for c in others)

    # pendtilt batch over the CSV logs, each with the rig (and a 3-D log's scenario) beside
    # it, as the example takes them: its summary's RMS [deg] and rows are the fleet table's.
    csv_rows = [r for r in back.itertuples(index=False) if r.log.endswith(".csv")]
    assert len(csv_rows) == 16
    cli("batch", *[logs / r.log for r in csv_rows], "-o", tmp_path / "batch", "-q")
    summary = pendtilt.read_csv(tmp_path / "batch" / "summary.csv")  # every number exact
    index = {Path(l).name: i for i, l in enumerate(summary["log"])}
    rms_columns = [c for c in summary if c.endswith("_rms_deg")]
    # Every estimator of both models, planar and 3-D, as in the fleet table.
    assert sorted(c[: -len("_rms_deg")] for c in rms_columns) == sorted(
        c[len("rms_") :] for c in back.columns if c.startswith("rms_")
    )
    for r in csv_rows:
        i = index[r.log]
        assert summary["rows"][i] == r.rows
        for c in rms_columns:
            name = f"rms_{c[: -len('_rms_deg')]}"
            want = math.degrees(getattr(r, name))
            assert summary[c][i] == want or (math.isnan(want) and math.isnan(summary[c][i])), c
