"""Rig files, the commands run from Python, and the streaming classes."""
import math

import numpy as np
import pytest

import pendtilt


def test_read_rig_and_write_rig_round_trip(scooter, tmp_path):
    _, rig_file = scooter
    rig = pendtilt.read_rig(rig_file)
    assert rig.kind == "planar"
    # simulate writes its rig as the library writes every rig: read back, the same text.
    assert rig.to_toml() == rig.canonical == rig_file.read_text()
    out = tmp_path / "copy.toml"
    pendtilt.write_rig(rig, out)
    assert out.read_text() == rig_file.read_text()
    assert pendtilt.read_rig(out) == rig
    # Through a dict and back.
    again = pendtilt.Rig.from_dict(rig.to_dict())
    assert again == rig
    changed = rig.with_settings("kalman", q_angle=0.002)
    assert changed.to_dict()["kalman"]["q_angle"] == 0.002
    assert changed != rig
    pendtilt.write_rig(changed.to_dict(), out)
    assert pendtilt.read_rig(out) == changed


def test_a_3d_rig_round_trips_and_a_bad_key_is_refused(cli, scooter3d, tmp_path):
    _, rig_file, _ = scooter3d
    rig = pendtilt.read_rig(rig_file)
    assert rig.kind == "3d"
    pendtilt.write_rig(rig, tmp_path / "r.toml")
    assert pendtilt.read_rig(tmp_path / "r.toml") == rig
    with pytest.raises(pendtilt.PendtiltError, match="nonesuch"):
        pendtilt.Rig.default().with_settings("kalman", nonesuch=1.0)
    # The 3-D default is the command's template.
    template = cli("rig", "--template", "3d").stdout
    assert pendtilt.Rig.default("3d").to_toml() == template
    assert pendtilt.Rig.default("3d").kind == "3d"
    # Settings of every kind through a dict (an infinite frequency included).
    ekf3d = pendtilt.Ekf3d(vibration_density=2.0, path_turn_hz=math.inf, adapt=False)
    assert ekf3d.names == ["ekf3d"]
    assert pendtilt.Rig.from_dict(pendtilt.Rig.default("3d").to_dict()) == pendtilt.Rig.default("3d")


def test_simulate_writes_the_commands_bytes(cli, tmp_path):
    cli("simulate", "--scenario", "sine", "--duration", "3", "--seed", "7", "-o",
        tmp_path / "cli.csv", "-q")
    sim = pendtilt.simulate("sine", tmp_path / "py.csv", duration=3, seed=7)
    assert sim.log.read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert sim.rig.read_bytes() == (tmp_path / "cli.rig.toml").read_bytes()
    assert set(sim.data) >= {"t", "phi", "gyro", "ax", "ay", "theta"}
    assert len(sim.data["t"]) == 3000
    # Without an output: a temporary file.
    tmp = pendtilt.simulate("still", duration=1)
    assert tmp.log.exists() and tmp.read_rig().kind == "planar"
    with pytest.raises(pendtilt.PendtiltError, match="nonesuch"):
        pendtilt.simulate("nonesuch", duration=1)


def test_fit_and_tune_give_the_commands_rigs(cli, scooter, tmp_path):
    log, rig = scooter
    cli("fit", log, "-o", tmp_path / "cli_fit.toml", "-q")
    fitted = pendtilt.fit(log)
    assert fitted.to_toml() == (tmp_path / "cli_fit.toml").read_text()
    cli("tune", log, "--params", rig, "--time-limit", "2", "-o", tmp_path / "cli_tune.toml", "-q")
    tuned = pendtilt.tune(log, params=pendtilt.read_rig(rig), time_limit=2)
    want = (tmp_path / "cli_tune.toml").read_text()
    assert tuned == pendtilt.read_rig(tmp_path / "cli_tune.toml")
    # The same file but for the comment naming the rig it started from (a temporary copy).
    keys = lambda text: [l for l in text.splitlines() if not l.startswith("#")]  # noqa: E731
    assert keys(tuned.to_toml()) == keys(want)


def test_fit_and_tune_of_a_3d_log_give_the_commands_rigs(cli, scooter3d, tmp_path):
    log, rig, _ = scooter3d
    cli("fit", log, "--params", rig, "-o", tmp_path / "cli_fit3d.toml", "-q")
    fitted = pendtilt.fit(log, params=pendtilt.read_rig(rig))
    assert fitted.kind == "3d"
    assert fitted == pendtilt.read_rig(tmp_path / "cli_fit3d.toml")
    # The start rig's [mounting] is kept, so estimate reads the speed's point.
    assert fitted.to_dict()["mounting"] == pendtilt.read_rig(rig).to_dict()["mounting"]
    cli("tune", log, "--params", rig, "-o", tmp_path / "cli_tune3d.toml", "-q")
    tuned = pendtilt.tune(log, params=pendtilt.read_rig(rig))
    assert tuned == pendtilt.read_rig(tmp_path / "cli_tune3d.toml")
    ekf3d = tuned.to_dict()["ekf3d"]
    assert ekf3d["adapt"] is True and 0.0 < ekf3d["adapt_min_factor"] <= 1.0
    assert ekf3d["adapt_max_factor"] > 1.0 and ekf3d["jerk_density"] > 0.0
    # A 3-D log with the other's option is refused by name.
    with pytest.raises(pendtilt.PendtiltError, match="--method newton: for planar logs only"):
        pendtilt.fit(log, method="newton")


def test_replay_of_a_table_runs_the_command(scooter3d, tmp_path):
    log, _, _ = scooter3d
    d = pendtilt.read_csv(log)
    imu = {k: d[k] for k in ("t", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az", "roll", "pitch")}
    out = pendtilt.replay(imu, tmp_path / "rep.csv", seed=2)
    cols = out.data
    assert {"phi_x", "phi_y"} <= set(cols) and len(cols["t"]) == len(d["t"])
    est = pendtilt.estimate(out.log, rig=out.rig, only="ekf3d")
    assert est.scores["ekf3d"][0] < math.radians(2)


def test_the_stream_gives_estimates_equal_to_estimate_on_a_clean_log(scooter):
    log, rig = scooter
    d = pendtilt.read_csv(log)
    n = 4000
    want = pendtilt.estimate({k: v[:n] for k, v in d.items()}, rig=rig)
    s = pendtilt.Stream(rig)
    assert s.names == want.names
    theta, flags = s.update_many(d["t"][:n], d["phi"][:n], d["gyro"][:n], d["ax"][:n], d["ay"][:n])
    for j, name in enumerate(s.names):
        np.testing.assert_array_equal(theta[:, j], want[name], err_msg=name)
        np.testing.assert_array_equal(flags[:, j], want.flags[name], err_msg=name)
    # One estimator's own class, one sample at a time, with a setting.
    ekf = pendtilt.Ekf(rig)
    got = [ekf.update(*(d[k][i] for k in ("t", "phi", "gyro", "ax", "ay"))) for i in range(n)]
    np.testing.assert_array_equal(got, want["ekf"])
    kf = pendtilt.KfAccel(rig, q_angle=0.01)
    assert kf.names[-1] == "kf_accel"  # with accel, which it reads
    assert isinstance(kf.update(0.0, 0.0, 0.0, 0.0, 9.81), float)


def test_every_estimator_has_a_class_and_the_3d_stream_matches_estimate(scooter3d):
    log, rig, scenario = scooter3d
    assert set(pendtilt.ESTIMATORS) >= {"ekf", "ekf3d", "vqf", "kf_fused"}
    for name, (cls, model, _) in pendtilt.ESTIMATORS.items():
        assert getattr(pendtilt, cls.__name__) is cls and model in ("planar", "3d")
    d = pendtilt.read_csv(log)
    n = 3000
    cols = ("t", "phi_x", "phi_y", "gyro_x", "gyro_y", "gyro_z", "ax", "ay", "az", "speed")
    want = pendtilt.estimate({k: d[k][:n] for k in cols}, rig=rig, scenario=scenario,
                             only="ekf3d")
    ekf = pendtilt.Ekf3d(rig, scenario)
    got = np.array([ekf.update(*(d[k][i] for k in cols)) for i in range(n)])
    np.testing.assert_array_equal(got[:, 0], want["ekf3d_roll"])
    np.testing.assert_array_equal(got[:, 1], want["ekf3d_pitch"])
    assert ekf.quaternion("ekf3d") is not None
    s = pendtilt.Stream3d(rig, scenario)
    assert "vqf" in s.names and set(s.update(*(d[k][0] for k in cols))) == set(s.names)


def test_flag_names_are_the_csvs():
    assert pendtilt.flag_names(0) == ""
    assert "|" in pendtilt.flag_names(3)


def test_the_stubs_name_every_estimator_class_and_function():
    from pathlib import Path

    stub = (Path(pendtilt.__file__).parent / "__init__.pyi").read_text()
    assert (Path(pendtilt.__file__).parent / "py.typed").exists()
    for name, (cls, model, _) in pendtilt.ESTIMATORS.items():
        base = "_Planar" if model == "planar" else "_Spatial"
        assert f"class {cls.__name__}({base}):" in stub, name
    for name in pendtilt.__all__:
        if name not in ("ESTIMATORS",):
            assert f"def {name}(" in stub or f"class {name}" in stub, name


def test_batch_functions_release_the_gil(scooter):
    import threading
    import time

    log, rig = scooter
    cols = pendtilt.read_csv(log)
    big = {k: np.tile(v, 10) for k, v in cols.items()}
    big["t"] = np.arange(len(big["t"])) * 1e-3
    done = threading.Event()
    worker = threading.Thread(
        target=lambda: (pendtilt.estimate(big, rig=rig, only="ekf,ukf,kf_fused"), done.set())
    )
    stamps = []
    start = time.perf_counter()
    worker.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    total = time.perf_counter() - start
    gaps = np.diff(stamps)
    # This thread ran all along: no pause near the length of the call.
    assert total > 0.2 and len(stamps) > 50 and gaps.max() < total / 4, (total, gaps.max())


def test_write_csv_writes_each_number_in_its_shortest_exact_form(tmp_path):
    t = np.array([0.0, 0.001, 0.002])
    x = np.array([0.1, np.nan, -1.0e-300])
    pendtilt.write_csv({"t": t, "a,b": x, "label": ["p", "q", "r"]}, tmp_path / "x.csv")
    text = (tmp_path / "x.csv").read_text()
    assert text.splitlines()[0] == 't,"a,b"'  # the text column is left out
    assert text.splitlines()[2:] == ["0.001,NaN", "0.002,-1e-300"]
    back = pendtilt.read_csv(tmp_path / "x.csv")
    assert back["t"].tolist() == t.tolist() and back["a,b"][2] == -1.0e-300
