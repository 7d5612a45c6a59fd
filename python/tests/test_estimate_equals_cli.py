"""pendtilt.estimate gives the command's estimates, bit for bit, and its messages."""
import math

import numpy as np
import pandas as pd
import pytest

import pendtilt


def same(a, b, name):
    """Exact equality, NaN where NaN (bit patterns of the finite values)."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    assert a.shape == b.shape, name
    nan_a, nan_b = np.isnan(a), np.isnan(b)
    assert np.array_equal(nan_a, nan_b), f"{name}: NaN at different rows"
    assert np.array_equal(a[~nan_a].view(np.int64), b[~nan_b].view(np.int64)), (
        f"{name}: differs at rows {np.flatnonzero(a != b)[:5]}"
    )


def read(path, **kw):
    """A CSV read by pandas with every number exact (pandas 3 parses exactly by default;
    older ones need the round-trip parser)."""
    if int(pd.__version__.split(".")[0]) < 3:
        kw["float_precision"] = "round_trip"
    return pd.read_csv(path, **kw)


def cli_estimates(cli, log, out, *args):
    """The command's estimates CSV, read exactly."""
    p = cli("estimate", log, "-o", out, *args)
    return read(out, keep_default_na=False, na_values=["NaN"]), p


def cli_error(p, out=None):
    """The command's error message (after `error: `), without the context a Python call
    has no part in: `OUT was not written: `."""
    assert p.returncode == 1
    message = p.stderr.strip().splitlines()[-1].removeprefix("error: ")
    if out is not None:
        message = message.removeprefix(f"{out} was not written: ")
    return message


def test_planar_estimates_from_a_dataframe_equal_the_commands(cli, scooter, tmp_path):
    log, rig = scooter
    want, _ = cli_estimates(cli, log, tmp_path / "est.csv", "--params", rig, "--flags")
    df = read(log)
    got = pendtilt.estimate(df, rig=rig, flags=True).to_pandas()
    assert list(got.columns) == list(want.columns)
    assert len(got) == len(want) == len(df)
    for c in want.columns:
        if c.endswith("_flags"):
            assert list(got[c]) == [("" if isinstance(v, float) else v) for v in want[c]], c
        else:
            same(got[c], want[c], c)


def test_planar_estimates_from_a_csv_path_and_arrays_equal_the_commands(cli, scooter, tmp_path):
    log, rig = scooter
    want, p = cli_estimates(cli, log, tmp_path / "est.csv", "--params", rig,
                            "--only", "ekf,kf_alg2,alg2,accel", "--out-deg")
    from_path = pendtilt.estimate(log, rig=pendtilt.read_rig(rig),
                                  only=["ekf", "kf_alg2", "alg2", "accel"], out_deg=True)
    arrays = pendtilt.read_csv(log)  # a dict of NumPy arrays
    from_arrays = pendtilt.estimate(arrays, rig=rig, only="ekf,kf_alg2,alg2,accel",
                                    out_deg=True)
    for got in (from_path, from_arrays):
        assert list(got.columns) == list(want.columns)
        for c in want.columns:
            same(got[c], want[c], c)
    # The error table is the one the command prints.
    assert from_path.error_table().rstrip("\n") in p.stdout
    assert from_arrays.error_table() == from_path.error_table()


def test_the_rms_errors_are_the_commands_sums(cli, scooter, tmp_path):
    log, rig = scooter
    want, _ = cli_estimates(cli, log, tmp_path / "est.csv", "--params", rig)
    got = pendtilt.estimate(log, rig=rig)
    theta = want["theta"].to_numpy()
    t = want["t"].to_numpy()
    assert got.score_from == 5.0
    for n in got.names:
        e = want[n].to_numpy() - theta
        ok = np.isfinite(e) & (t >= t[0] + 5.0)  # scored from 5 s after the first row
        # Summed in row order, as the command sums.
        rms = math.sqrt(np.cumsum(e[ok] * e[ok])[-1] / ok.sum())
        assert got.rms[n] == rms, n


def test_3d_estimates_equal_the_commands(cli, scooter3d, tmp_path):
    log, rig, scenario = scooter3d
    want, p = cli_estimates(cli, log, tmp_path / "est3d.csv", "--params", rig, "--scenario",
                            scenario, "--quaternion", "--flags")
    df = read(log)
    for data in (df, log):
        got = pendtilt.estimate(data, rig=rig, scenario=scenario, quaternion=True,
                                flags=True).to_pandas()
        assert list(got.columns) == list(want.columns)
        for c in want.columns:
            if c.endswith("_flags"):
                assert list(got[c]) == [("" if isinstance(v, float) else v) for v in want[c]], c
            else:
                same(got[c], want[c], c)
    est = pendtilt.estimate(log, rig=rig, scenario=scenario)
    # The score table's RMS column, as the command prints it (5 decimals, degrees).
    for n, s in est.scores.items():
        line = next(l for l in p.stdout.splitlines() if l.split()[:1] == [n])
        assert line.split()[1] == f"{math.degrees(s[0]):.5f}", n


def test_errors_are_the_commands_messages(cli, scooter, tmp_path):
    log, rig = scooter
    out = tmp_path / "x.csv"
    p = cli("estimate", log, "-o", out, "--only", "ekf,nonesuch", check=False)
    message = cli_error(p, out)
    assert message.startswith("unknown estimator `nonesuch`")
    with pytest.raises(pendtilt.PendtiltError) as e:
        pendtilt.estimate(log, only=["ekf", "nonesuch"])
    assert str(e.value) == message
    assert isinstance(e.value, ValueError)

    # A cell that is no number: the same file, line and column named.
    bad = tmp_path / "bad.csv"
    bad.write_text("t,phi,gyro\n0,0,0\n0.001,abc,0\n")
    out = tmp_path / "y.csv"
    p = cli("estimate", bad, "-o", out, check=False)
    message = cli_error(p, out)
    with pytest.raises(pendtilt.PendtiltError) as e:
        pendtilt.estimate(bad)
    assert str(e.value) == message
    assert "bad.csv:3" in str(e.value)


def test_a_bad_rig_file_raises_the_commands_message(cli, scooter, tmp_path):
    log, _ = scooter
    rig = tmp_path / "bad.rig.toml"
    rig.write_text("[pendulum]\na = -1.0\nb = 0.005\n")
    out = tmp_path / "z.csv"
    p = cli("estimate", log, "-o", out, "--params", rig, check=False)
    message = cli_error(p, out)
    with pytest.raises(pendtilt.PendtiltError) as e:
        pendtilt.estimate(log, rig=rig)
    assert str(e.value) == message
    with pytest.raises(pendtilt.PendtiltError) as e2:
        pendtilt.read_rig(rig)
    assert str(e2.value) in message


def test_mapped_columns_in_degrees_equal_the_commands(cli, scooter, tmp_path):
    log, rig = scooter
    df = read(log).rename(columns={"phi": "enc", "gyro": "gz"})
    df["enc"] = np.degrees(df["enc"])
    df["gz"] = np.degrees(df["gz"])
    mine = tmp_path / "mine.csv"
    pendtilt.write_csv(df, mine)
    want, _ = cli_estimates(cli, mine, tmp_path / "est.csv", "--params", rig, "--map",
                            "phi=enc,gyro=gz", "--deg", "phi,gyro", "--score-from", "2")
    got = pendtilt.estimate(df, rig=rig, map={"phi": "enc", "gyro": "gz"}, deg=["phi", "gyro"],
                            score_from=2)
    assert got.score_from == 2.0
    assert list(got.columns) == list(want.columns)
    for c in want.columns:
        same(got[c], want[c], c)
