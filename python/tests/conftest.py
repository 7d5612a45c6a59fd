"""Shared fixtures: the `pendtilt` command (built with cargo when not given) and logs."""
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    """The command: $PENDTILT_BIN, else the release build of this checkout (built now if
    it is missing; cargo's own check makes a warm build quick)."""
    given = os.environ.get("PENDTILT_BIN")
    if given:
        return Path(given)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.fail("cargo is not on PATH: set PENDTILT_BIN to a pendtilt binary")
    subprocess.run(
        [cargo, "build", "--release", "-q", "-p", "pendtilt"], cwd=ROOT, check=True
    )
    return target / "release" / "pendtilt"


@pytest.fixture(scope="session")
def cli():
    """Runs the `pendtilt` command; returns the CompletedProcess (text)."""
    binary = _binary()

    def run(*args, check=True):
        p = subprocess.run(
            [str(binary), *[str(a) for a in args]], capture_output=True, text=True
        )
        if check and p.returncode != 0:
            raise AssertionError(f"pendtilt {' '.join(map(str, args))}: {p.stderr}")
        return p

    run.binary = binary
    return run


@pytest.fixture(scope="session")
def scooter(cli, tmp_path_factory):
    """A 20 s planar scooter ride written by the command: (log, rig)."""
    d = tmp_path_factory.mktemp("scooter")
    log = d / "ride.csv"
    cli("simulate", "--scenario", "scooter", "--duration", "20", "--seed", "3", "-o", log, "-q")
    return log, d / "ride.rig.toml"


@pytest.fixture(scope="session")
def scooter3d(cli, tmp_path_factory):
    """A 12 s 3-D scooter ride written by the command: (log, rig, scenario)."""
    d = tmp_path_factory.mktemp("scooter3d")
    log = d / "sc.csv"
    cli("simulate", "--scenario", "scooter3d", "--duration", "12", "-o", log, "-q")
    return log, d / "sc.rig.toml", d / "sc.scenario.toml"
