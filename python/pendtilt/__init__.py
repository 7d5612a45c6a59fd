"""pendtilt: the tilt of a moving body from a pendulum sensor, in Python.

The estimators, simulator, fitting and tuning of the Rust library ``pendtilt``, called
through the code the ``pendtilt`` command runs: the same options, defaults, estimates
(bit for bit) and error messages. SI units throughout (rad, rad/s, m/s^2, s) unless an
option asks for degrees.

Batch functions: :func:`estimate`, :func:`simulate`, :func:`replay`, :func:`fit`,
:func:`tune`, :func:`read_rig`, :func:`write_rig`, :func:`read_csv`, :func:`write_csv`.
Streaming: :class:`Stream` (every planar estimator), :class:`Stream3d` (every 3-D one),
and one class per estimator (:class:`Ekf`, :class:`Alg2`, :class:`KfAccel`, ...,
:class:`Ekf3d`, :class:`Vqf`, ...; :data:`ESTIMATORS` lists them). Errors raise
:class:`PendtiltError` (a ``ValueError``) with the command's message.
"""
from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _pendtilt
from ._pendtilt import PendtiltError, flag_names

try:  # Python 3.11+
    import tomllib as _toml
except ImportError:  # pragma: no cover - older Pythons
    import tomli as _toml  # type: ignore[no-redef]

__version__ = "0.1.0"

PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "PendtiltError",
    "Rig",
    "Estimates",
    "Simulation",
    "Stream",
    "Stream3d",
    "ESTIMATORS",
    "estimate",
    "simulate",
    "replay",
    "fit",
    "tune",
    "read_rig",
    "write_rig",
    "read_csv",
    "write_csv",
    "flag_names",
    "run",
    "catalogue",
    "library_version",
]


def library_version() -> str:
    """The version (and commit) of the pendtilt library the native module was built from."""
    return _pendtilt.version()


def catalogue() -> List[Dict[str, Any]]:
    """Every estimator, planar then 3-D, as the command lists them: ``name``, ``model``
    (``"planar"`` or ``"3d"``), ``family`` (Raw, Paper, Kalman, ModelBased, Peers: the
    panels of the report's figures), ``reads`` (the sensors) and ``about``."""
    keys = ("name", "model", "family", "reads", "about")
    return [dict(zip(keys, row)) for row in _pendtilt.catalogue()]


def run(*args: str) -> None:
    """Runs a ``pendtilt`` command line in this process, e.g.
    ``pendtilt.run("simulate", "--scenario", "scooter", "-o", "ride.csv")``: the command
    itself, its notices on standard error. Raises :class:`PendtiltError` on an error."""
    _pendtilt.run_cli(["pendtilt", *[str(a) for a in args]])


# ---------------------------------------------------------------------------------------
# Rig files


class Rig:
    """A rig file (TOML): the pendulum and every estimator's settings, SI units.

    A planar rig (tables ``pendulum``, ``kalman``, ``differentiator``, ``accel``,
    ``gyro``, ``alg1``, ``alg2``, ``alg3``, ``ekf``) is checked and kept as the command
    writes it (``text``: every key with its unit); a 3-D rig (``pendulum3d``,
    ``mounting``, ``ekf3d``, ``gyro``) is checked and kept as given. An invalid rig raises
    :class:`PendtiltError` with the command's message.
    """

    def __init__(self, text: str, origin: str = "<rig>") -> None:
        kind, canonical, doubts = _pendtilt.rig_check(text, origin)
        #: ``"planar"`` or ``"3d"``.
        self.kind: str = kind
        #: The TOML text as given (a file's, comments and all), which :func:`write_rig`
        #: writes back.
        self.text: str = text
        #: A planar rig as the command writes it (every key with its unit); a 3-D rig's
        #: text as given. Two planar rigs are equal when these are, two 3-D rigs when
        #: their tables are.
        self.canonical: str = canonical if canonical is not None else text
        #: The rig's doubtful values, as the command warns about them.
        self.doubts: List[str] = list(doubts)

    __hash__ = None  # type: ignore[assignment]

    @classmethod
    def default(cls, kind: str = "planar") -> "Rig":
        """The default rig, every key written out: ``"planar"`` (MODEL.md section 5) or
        ``"3d"`` (MODEL.md 7.6; ``pendtilt rig --template 3d``)."""
        return cls(_pendtilt.rig_default(kind), f"<default {kind} rig>")

    @classmethod
    def from_dict(cls, tables: Mapping[str, Mapping[str, Any]]) -> "Rig":
        """A rig from its tables, e.g. ``{"pendulum": {"a": 0.02, "b": 0.005}}``."""
        return cls(_toml_of(tables), "<dict>")

    def to_dict(self) -> Dict[str, Dict[str, Any]]:
        """The tables as a dict."""
        return _toml.loads(self.text)

    def to_toml(self) -> str:
        """The TOML text, as :func:`write_rig` writes it."""
        return self.text

    def with_settings(self, table: str, **values: Any) -> "Rig":
        """A copy with the keys of ``table`` set to ``values`` (checked as a rig file)."""
        d = self.to_dict()
        d.setdefault(table, {}).update(values)
        return Rig.from_dict(d)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Rig) or self.kind != other.kind:
            return False
        if self.kind == "3d":  # no canonical text: the same tables and values
            return self.to_dict() == other.to_dict()
        return self.canonical == other.canonical

    def __repr__(self) -> str:
        return f"Rig(kind={self.kind!r}, tables={list(self.to_dict())})"


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        x = float(v)
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf") if math.isinf(x) else repr(x)
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise PendtiltError(f"not a rig value: {v!r}")


def _toml_of(tables: Mapping[str, Any], prefix: str = "") -> str:
    """TOML text of nested tables (the rig's tables of numbers, booleans and arrays)."""
    keys = [f"{k} = {_toml_value(v)}\n" for k, v in tables.items() if not isinstance(v, Mapping)]
    out = (f"[{prefix}]\n" if prefix and keys else "") + "".join(keys)
    for k, v in tables.items():
        if isinstance(v, Mapping):
            name = f"{prefix}.{k}" if prefix else k
            out += ("\n" if out else "") + (f"[{name}]\n" if not v else "") + _toml_of(v, name)
    return out


def read_rig(path: PathLike) -> Rig:
    """Reads a rig file as the command reads it (errors name the file)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as e:
        raise PendtiltError(f"{p}: cannot read the rig file: {e}") from None
    return Rig(text, str(p))


def write_rig(rig: Union[Rig, Mapping[str, Any]], path: PathLike) -> None:
    """Writes ``rig`` (a :class:`Rig` or its tables) as a rig file that the command and
    :func:`read_rig` read back to an equal rig."""
    r = rig if isinstance(rig, Rig) else Rig.from_dict(rig)
    Path(path).write_text(r.to_toml(), encoding="utf-8")


RigLike = Union[None, PathLike, Rig, Mapping[str, Any]]


class _Files:
    """Temporary files for the rigs given as objects (removed with this object)."""

    def __init__(self) -> None:
        self._dir: Optional[tempfile.TemporaryDirectory] = None

    def path(self, name: str) -> Path:
        if self._dir is None:
            self._dir = tempfile.TemporaryDirectory(prefix="pendtilt-")
        return Path(self._dir.name) / name

    def rig(self, rig: RigLike, name: str = "rig.toml") -> Optional[str]:
        if rig is None:
            return None
        if isinstance(rig, (str, os.PathLike)):
            return os.fspath(rig)
        r = rig if isinstance(rig, Rig) else Rig.from_dict(rig)
        p = self.path(name)
        p.write_text(r.to_toml(), encoding="utf-8")
        return str(p)

    def close(self) -> None:
        if self._dir is not None:
            self._dir.cleanup()
            self._dir = None


def _options(**options: Any) -> List[str]:
    """Keyword arguments as the command's options: ``a_b=x`` is ``--a-b x``; True a flag
    alone; False or None left out; a list joined by commas; a dict ``k=v`` pairs."""
    argv: List[str] = []
    for key, value in options.items():
        if value is None or value is False:
            continue
        flag = "--" + key.replace("_", "-")
        if value is True:
            argv.append(flag)
        elif isinstance(value, Mapping):
            argv.append(f"{flag}=" + ",".join(f"{k}={v}" for k, v in value.items()))
        elif isinstance(value, (list, tuple)):
            argv.append(f"{flag}=" + ",".join(str(v) for v in value))
        else:
            argv.append(f"{flag}={value}")
    return argv


# ---------------------------------------------------------------------------------------
# Tables


def read_csv(path: PathLike) -> Dict[str, Any]:
    """Reads a CSV table (a log, or an output of the command): each numeric column as a
    float64 array holding its cells' exact values (empty: NaN), any other column (the
    ``_flags`` columns) as a list of str. Keys in column order."""
    names, columns = _pendtilt.read_csv(os.fspath(path))
    return dict(zip(names, columns))


def write_csv(data: Any, path: PathLike) -> None:
    """Writes a table (a dict of arrays, a DataFrame) as a CSV log, every number in the
    shortest form that reads back to the same value (NaN when missing), as the command
    writes its outputs."""
    names, columns = _columns_of(data)
    _pendtilt.write_csv(os.fspath(path), names, columns)


def _columns_of(data: Any) -> Tuple[List[str], List[np.ndarray]]:
    """A table's names and float64 columns: a DataFrame, a dict of arrays, or a NumPy
    structured array. Non-numeric columns are left out (the readers ignore them)."""
    if hasattr(data, "columns") and hasattr(data, "to_numpy"):  # a DataFrame
        items = [(str(c), data[c].to_numpy()) for c in data.columns]
    elif isinstance(data, np.ndarray) and data.dtype.names:
        items = [(n, data[n]) for n in data.dtype.names]
    elif isinstance(data, Mapping):
        items = [(str(k), np.asarray(v)) for k, v in data.items()]
    else:
        raise PendtiltError(
            "a log is a path (CSV or Parquet), a dict of arrays or a DataFrame, not "
            f"{type(data).__name__}"
        )
    names, cols = [], []
    for n, v in items:
        a = np.asarray(v)
        if a.dtype.kind in "biuf":
            names.append(n)
            cols.append(np.ascontiguousarray(a, dtype=np.float64).reshape(-1))
    return names, cols


def _read_table(path: PathLike) -> Dict[str, np.ndarray]:
    """A Parquet file as a dict of columns (pyarrow)."""
    import pyarrow.parquet as pq

    t = pq.read_table(os.fspath(path))
    return {n: t.column(n).to_numpy() for n in t.column_names}


# ---------------------------------------------------------------------------------------
# estimate


class Estimates:
    """What :func:`estimate` computed: the columns of ``pendtilt estimate``'s CSV as
    arrays, and its summary.

    ``columns``: ``t``, then per estimator its tilt (planar: ``<name>``; 3-D:
    ``<name>_roll``, ``<name>_pitch`` and with ``quaternion=True`` ``<name>_qw`` ...
    ``_qz``), then the truth (planar ``theta``; 3-D ``roll``, ``pitch``) when the log has
    it; in the CSV's order, rad (degrees with ``out_deg=True``). ``flags``: per
    estimator, its flag bits per row (:func:`flag_names` gives their names).
    """

    def __init__(self, raw: Dict[str, Any], with_flags: bool) -> None:
        #: ``"planar"`` or ``"3d"``.
        self.model: str = raw["model"]
        #: The estimators, in column order.
        self.names: List[str] = list(raw["names"])
        #: Rows read (one output row each).
        self.rows: int = int(raw["rows"])
        #: The input's warnings, as the command prints them after ``warning: ``.
        self.warnings: List[str] = list(raw["warnings"])
        #: The count of warnings of the log reader (listed or not).
        self.warning_count: int = int(raw["warning_count"])
        #: The command's notes (columns found, estimators skipped).
        self.notes: List[str] = list(raw["notes"])
        self.flags: Dict[str, np.ndarray] = dict(raw["flags"])
        self._with_flags = with_flags
        cols: Dict[str, np.ndarray] = {"t": raw["t"]}
        if self.model == "planar":
            cols.update(raw["estimates"])
            if raw["theta"] is not None:
                cols["theta"] = raw["theta"]
            #: Planar: per estimator (RMS, max |error|, samples, missing) against
            #: ``theta`` [rad] from ``score_from`` on, as the command's table; None
            #: without a true angle.
            self.errors: Optional[Dict[str, Tuple[float, float, int, int]]] = (
                None if raw["errors"] is None else {n: tuple(e) for n, e in raw["errors"]}
            )
            self._table: Optional[str] = raw["error_table"]
            #: 3-D: per estimator (RMS, max, mean, scored rows, missing) of the
            #: inclination error [rad]; None on a planar log.
            self.scores: Optional[Dict[str, Tuple[float, float, float, int, int]]] = None
        else:
            for n in self.names:
                cols[f"{n}_roll"] = raw["roll"][n]
                cols[f"{n}_pitch"] = raw["pitch"][n]
                if n in raw["quaternion"]:
                    for part, a in zip(("qw", "qx", "qy", "qz"), raw["quaternion"][n]):
                        cols[f"{n}_{part}"] = a
            if raw["truth"] is not None:
                cols["roll"], cols["pitch"] = raw["truth"]
            self.errors = None
            self._table = None
            self.scores = (
                None if raw["scores"] is None else {n: tuple(s) for n, s in raw["scores"]}
            )
        #: The errors were scored from this long after the first row [s].
        self.score_from: Optional[float] = raw.get("score_from")
        #: The columns of the estimates CSV, in its order.
        self.columns: Dict[str, np.ndarray] = cols

    @property
    def rms(self) -> Dict[str, float]:
        """Per estimator, its RMS error [rad] (planar: against ``theta``; 3-D: the
        inclination error); empty without the truth."""
        if self.errors is not None:
            return {n: e[0] for n, e in self.errors.items()}
        if self.scores is not None:
            return {n: s[0] for n, s in self.scores.items()}
        return {}

    def error_table(self) -> Optional[str]:
        """The planar error table exactly as ``pendtilt estimate`` prints it."""
        return self._table

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __len__(self) -> int:
        return self.rows

    def flag_texts(self, name: str) -> List[str]:
        """Estimator ``name``'s flags per row as the CSV's ``<name>_flags`` column."""
        cache: Dict[int, str] = {}
        out = []
        for b in self.flags[name].tolist():
            s = cache.get(b)
            if s is None:
                s = cache[b] = flag_names(b)
            out.append(s)
        return out

    def to_dict(self, flags: Optional[bool] = None) -> Dict[str, Any]:
        """The columns as the CSV has them, with the ``<name>_flags`` text columns when
        ``flags`` (default: when :func:`estimate` was asked for them)."""
        d: Dict[str, Any] = dict(self.columns)
        if self._with_flags if flags is None else flags:
            for n in self.names:
                d[f"{n}_flags"] = self.flag_texts(n)
        return d

    def to_pandas(self, flags: Optional[bool] = None) -> Any:
        """The columns as a pandas DataFrame (see :meth:`to_dict`)."""
        import pandas as pd

        return pd.DataFrame(self.to_dict(flags))

    def __repr__(self) -> str:
        return f"Estimates({self.model}, {self.rows} rows, {self.names})"


def estimate(
    data: Any,
    rig: RigLike = None,
    *,
    scenario: Optional[PathLike] = None,
    only: Optional[Union[str, Sequence[str]]] = None,
    map: Optional[Union[str, Mapping[str, str]]] = None,
    deg: Union[None, bool, str, Sequence[str]] = None,
    time_unit: Optional[str] = None,
    accel_unit: Optional[str] = None,
    negate: Optional[Union[str, Sequence[str]]] = None,
    flags: bool = False,
    out_deg: bool = False,
    quaternion: bool = False,
    score_from: Optional[float] = None,
    name: Optional[str] = None,
) -> Estimates:
    """Runs every estimator whose inputs are present over a log: ``pendtilt estimate``.

    ``data``: a CSV file (read as the command reads it), a Parquet file, a dict of
    arrays, a DataFrame, or a NumPy structured array, with the columns of MODEL.md
    section 5 (``t, phi, gyro, ax, ay[, theta]``) or 7.6 (3-D: ``t, phi_x, phi_y,
    gyro_x, gyro_y, gyro_z, ax, ay, az[, speed, roll, pitch]``). The estimates equal the
    command's on the same numbers, bit for bit.

    Options (each the command's, with its default): ``rig`` (``--params``: a path, a
    :class:`Rig` or its tables; default MODEL.md's rig), ``scenario`` (3-D, the scenario
    file; default none), ``only`` (estimator names; default every one the columns feed),
    ``map`` (``{"phi": "enc"}``; default the MODEL.md names), ``deg`` (True: every
    angular column in degrees, or a list; default none), ``time_unit`` (s, ms, us, ns;
    default s), ``accel_unit`` (m/s2, g, mg; default m/s2), ``negate`` (columns counting
    the other way; default none), ``flags`` (the ``_flags`` text columns in
    :meth:`Estimates.to_pandas`; default False), ``out_deg`` (estimates in degrees;
    default False), ``quaternion`` (3-D: ekf3d/ukf3d quaternions; default False),
    ``score_from`` (the errors are scored from this long after the first row [s];
    default the 3-D scenario's, else 5, or 0 for a log shorter than 10 s). ``name`` names an in-memory table in messages (default ``<memory>``).
    """
    files = _Files()
    try:
        names = columns = None
        if isinstance(data, (str, os.PathLike)):
            p = Path(data)
            if p.suffix.lower() in (".parquet", ".pq"):
                names, columns = _columns_of(_read_table(p))
                log = name or str(p)
            else:
                log = str(p)
        else:
            names, columns = _columns_of(data)
            log = name or "<memory>"
        argv = ["pendtilt", "estimate", log, "-o", "-"]
        argv += _options(
            params=files.rig(rig),
            scenario=None if scenario is None else os.fspath(scenario),
            only=[only] if isinstance(only, str) else only,
            map=map,
            deg="all" if deg is True else ([deg] if isinstance(deg, str) else deg),
            time_unit=time_unit,
            accel_unit=accel_unit,
            negate=[negate] if isinstance(negate, str) else negate,
            out_deg=out_deg,
            quaternion=quaternion,
            score_from=score_from,
        )
        argv.append("--quiet")
        raw = _pendtilt.estimate(argv, names, columns)
        return Estimates(raw, flags)
    finally:
        files.close()


# ---------------------------------------------------------------------------------------
# simulate, replay, fit, tune: the commands themselves


class Simulation:
    """A log written by :func:`simulate` or :func:`replay`: its files, and its columns."""

    def __init__(self, log: Path, rig: Path, scenario: Optional[Path], keep: Any) -> None:
        #: The log (CSV).
        self.log: Path = log
        #: The rig file written beside it.
        self.rig: Path = rig
        #: The resolved scenario file written beside it (``pendtilt simulate --config``
        #: reruns it; a 3-D one is :func:`estimate`'s ``scenario``), else None.
        self.scenario: Optional[Path] = scenario
        self._keep = keep  # the temporary directory, when no output was given
        self._data: Optional[Dict[str, Any]] = None

    @property
    def data(self) -> Dict[str, Any]:
        """The log's columns (:func:`read_csv`), read once."""
        if self._data is None:
            self._data = read_csv(self.log)
        return self._data

    def to_pandas(self) -> Any:
        """The log as a pandas DataFrame."""
        import pandas as pd

        return pd.DataFrame(self.data)

    def read_rig(self) -> Rig:
        """The rig file written beside the log."""
        return read_rig(self.rig)

    def __repr__(self) -> str:
        return f"Simulation(log={str(self.log)!r})"


def _output(output: Optional[PathLike], default: str) -> Tuple[Path, Any]:
    if output is not None:
        return Path(output), None
    keep = tempfile.TemporaryDirectory(prefix="pendtilt-")
    return Path(keep.name) / default, keep


def _beside(log: Path, suffix: str) -> Path:
    return log.with_name(log.stem + suffix)


def simulate(
    scenario: str = "scooter",
    output: Optional[PathLike] = None,
    *,
    seed: Optional[int] = None,
    duration: Optional[float] = None,
    rig: RigLike = None,
    quiet: bool = True,
    **options: Any,
) -> Simulation:
    """Simulates the rig on a moving body: ``pendtilt simulate --scenario SCENARIO``.

    ``scenario``: still, sigmoid, step, sine, chirp, scooter; still3d, scooter3d, ship3d,
    ride3d (default scooter). ``output``: the log to write (default: a temporary file,
    removed with the returned object); the rig (and 3-D scenario) file is written beside
    it. ``seed`` (default 1), ``duration`` [s] (default the scenario's), ``rig`` (the
    pendulum of a rig file), and every other option of the command as a keyword
    (``no_noise=True``, ``rate=500``, ``set=["vibration.scale=2"]``, ...; defaults in
    ``pendtilt simulate --help``).
    """
    files = _Files()
    try:
        out, keep = _output(output, "log.csv")
        sets = options.pop("set", None)
        argv = ["simulate", "--scenario", scenario, "-o", str(out)]
        argv += _options(seed=seed, duration=duration, rig=files.rig(rig), quiet=quiet, **options)
        for s in [sets] if isinstance(sets, str) else (sets or []):
            argv += ["--set", s]
        run(*argv)
    finally:
        files.close()
    scen = _beside(out, ".scenario.toml")
    return Simulation(out, _beside(out, ".rig.toml"), scen if scen.exists() else None, keep)


def replay(
    imu: Any,
    output: Optional[PathLike] = None,
    *,
    params: RigLike = None,
    quiet: bool = True,
    **options: Any,
) -> Simulation:
    """Puts a virtual pendulum on a recorded IMU: ``pendtilt replay IMU``.

    ``imu``: a CSV file (or a BROAD trial, MATLAB v5), or a table (dict of arrays,
    DataFrame: ``t, gyro_x, gyro_y, gyro_z, ax, ay, az``, optional truth), written to a
    temporary CSV first. ``output``: the 3-D log to write (default: a temporary file).
    ``params``: the rig whose ``[pendulum3d]`` is the virtual pendulum (default MODEL.md
    7.6's). Every other option of the command as a keyword (``vibration="scooter3d"``,
    ``seed=2``, ``deg="gyro"``, ...; defaults in ``pendtilt replay --help``).
    """
    files = _Files()
    try:
        out, keep = _output(output, "replayed.csv")
        if not isinstance(imu, (str, os.PathLike)):
            p = files.path("imu.csv")
            write_csv(imu, p)
            imu = p
        argv = ["replay", os.fspath(imu), "-o", str(out)]
        argv += _options(params=files.rig(params), quiet=quiet, **options)
        run(*argv)
    finally:
        files.close()
    return Simulation(out, _beside(out, ".rig.toml"), None, keep)


def _log_path(log: Any, files: _Files) -> str:
    if isinstance(log, (str, os.PathLike)):
        return os.fspath(log)
    p = files.path("log.csv")
    write_csv(log, p)
    return str(p)


def fit(
    log: Any,
    output: Optional[PathLike] = None,
    *,
    params: RigLike = None,
    quiet: bool = True,
    **options: Any,
) -> Rig:
    """Fits the pendulum's parameters to a log with a true angle: ``pendtilt fit LOG``.

    ``log``: a CSV file or a table. Returns the fitted rig (also written to ``output``
    when given). ``params``: the starting rig (default MODEL.md's). Every other option
    of the command as a keyword (``method="lm"``, ``target="gyro"``, ``algorithm="alg3"``,
    ...; defaults in ``pendtilt fit --help``).
    """
    files = _Files()
    try:
        out = Path(output) if output is not None else files.path("fitted.toml")
        argv = ["fit", _log_path(log, files), "-o", str(out)]
        argv += _options(params=files.rig(params, "params.toml"), quiet=quiet, **options)
        run(*argv)
        return read_rig(out)
    finally:
        files.close()


def tune(
    log: Any,
    output: Optional[PathLike] = None,
    *,
    params: RigLike = None,
    quiet: bool = True,
    **options: Any,
) -> Rig:
    """Tunes every estimator's settings from a log (no true angle needed): ``pendtilt
    tune LOG``. Returns the tuned rig (also written to ``output`` when given).
    ``params``: the rig to start from (default MODEL.md's). Every other option of the
    command as a keyword (``target="truth"``, ``time_limit=30``, ...; defaults in
    ``pendtilt tune --help``).
    """
    files = _Files()
    try:
        out = Path(output) if output is not None else files.path("tuned.toml")
        argv = ["tune", _log_path(log, files), "-o", str(out)]
        argv += _options(params=files.rig(params, "params.toml"), quiet=quiet, **options)
        run(*argv)
        return read_rig(out)
    finally:
        files.close()


# ---------------------------------------------------------------------------------------
# Streaming

_NAN = math.nan


class Stream:
    """The planar estimators, one sample at a time (the bank ``pendtilt estimate`` and
    ``pendtilt stream`` run).

    ``rig``: a rig file path, a :class:`Rig` or its tables (default MODEL.md's rig).
    ``estimators``: names (default every one the ``sensors`` feed). ``sensors``: which of
    ``phi``, ``gyro``, ``accel`` the samples carry (default all three). The samples go to
    the estimators as given: the log reader's checks (plausibility bounds, clips found
    ahead, units) are :func:`estimate`'s.
    """

    def __init__(
        self,
        rig: RigLike = None,
        estimators: Optional[Sequence[str]] = None,
        sensors: Sequence[str] = ("phi", "gyro", "accel"),
    ) -> None:
        files = _Files()
        try:
            est = None if estimators is None else list(estimators)
            self._s = _pendtilt.Stream(files.rig(rig), est, list(sensors))
        finally:
            files.close()
        #: The estimators, in output order.
        self.names: List[str] = list(self._s.names)

    def update(
        self, t: float, phi: float = _NAN, gyro: float = _NAN, ax: float = _NAN, ay: float = _NAN
    ) -> Dict[str, float]:
        """One sample at time ``t`` [s]: ``phi`` [rad], ``gyro`` [rad/s], ``ax``, ``ay``
        [m/s^2] (NaN or left out: missing). Each estimator's tilt [rad] (NaN while it
        has none)."""
        return dict(zip(self.names, self._s.update(t, phi, gyro, ax, ay)))

    def flags(self) -> Dict[str, int]:
        """The flag bits of the last update per estimator (:func:`flag_names`)."""
        return dict(zip(self.names, self._s.flags()))

    def update_many(
        self, t: Any, phi: Any = None, gyro: Any = None, ax: Any = None, ay: Any = None
    ) -> Tuple[np.ndarray, np.ndarray]:
        """Many samples (arrays; None: missing): tilts [rad] and flags, shape
        (samples, estimators)."""
        t = np.ascontiguousarray(t, dtype=np.float64)
        full = lambda a: (  # noqa: E731
            np.full(t.shape, np.nan) if a is None else np.ascontiguousarray(a, dtype=np.float64)
        )
        return self._s.update_many(t, full(phi), full(gyro), full(ax), full(ay))

    def reset(self) -> None:
        """Every estimator back to its start."""
        self._s.reset()


class Stream3d:
    """The 3-D estimators, one sample at a time, set up as ``pendtilt estimate`` sets them
    up for a 3-D log.

    ``rig``: a 3-D rig file (``[pendulum3d]``, ``[mounting]``, ``[ekf3d]``, ``[gyro]``),
    a :class:`Rig` or its tables (default: the scenario's rig, else MODEL.md 7.6's).
    ``scenario``: the scenario file ``simulate`` writes beside a 3-D log (its sensor
    noise figures set ekf3d/ukf3d's; default none, their default figures).
    ``estimators``: names (default every 3-D estimator).
    """

    def __init__(
        self,
        rig: RigLike = None,
        scenario: Optional[PathLike] = None,
        estimators: Optional[Sequence[str]] = None,
    ) -> None:
        files = _Files()
        try:
            est = None if estimators is None else list(estimators)
            scen = None if scenario is None else os.fspath(scenario)
            self._s = _pendtilt.Stream3d(files.rig(rig), scen, est)
        finally:
            files.close()
        #: The estimators, in output order.
        self.names: List[str] = list(self._s.names)

    def update(
        self,
        t: float,
        phi_x: float,
        phi_y: float,
        gyro_x: float,
        gyro_y: float,
        gyro_z: float,
        ax: float,
        ay: float,
        az: float,
        speed: float = _NAN,
    ) -> Dict[str, Tuple[float, float]]:
        """One sample at time ``t`` [s]: encoder angles [rad], body rates [rad/s],
        specific force [m/s^2] (FLU axes), the vehicle's speed [m/s] (default unknown).
        Each estimator's (roll, pitch) [rad]."""
        out = self._s.update(t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az, speed)
        return dict(zip(self.names, out))

    def flags(self) -> Dict[str, int]:
        """The flag bits of the last update per estimator (:func:`flag_names`)."""
        return dict(zip(self.names, self._s.flags()))

    def quaternion(self, name: str) -> Optional[Tuple[float, float, float, float]]:
        """Estimator ``name``'s attitude quaternion (w, x, y, z; world <- body), for those
        that have one (ekf3d, ukf3d)."""
        q = self._s.quaternion(self.names.index(name))
        return None if q is None else tuple(q)  # type: ignore[return-value]


# One class per estimator --------------------------------------------------------------

#: The rig table whose keys an estimator's class takes as keyword settings.
_TABLE = {
    "accel": "accel",
    "alg1": "alg1",
    "alg2": "alg2",
    "alg2_offset": "alg2",
    "alg2_dc": "alg2",
    "alg3": "alg3",
    "kf_accel": "kalman",
    "kf_alg1": "kalman",
    "kf_alg2": "kalman",
    "kf_alg3": "kalman",
    "kf_fused": "kalman",
    "ekf": "ekf",
    "ukf": "ekf",
    "ekf3d": "ekf3d",
    "ukf3d": "ekf3d",
    "imu3d": "ekf3d",
}


#: The keys of the ``[ekf]`` table (planar ekf, ukf).
_KEYS_EKF = (
    "encoder_bits", "encoder_noise", "encoder_jitter", "gyro_density", "gyro_bias",
    "accel_density", "accel_vibration", "process_jerk", "process_pendulum", "process_bias",
    "adapt",
)
#: The keys of the ``[ekf3d]`` table (ekf3d, ukf3d, imu3d).
_KEYS_EKF3D = (
    "vibration_density", "angular_accel_hz", "angular_accel_lead", "speed_noise",
    "jerk_density", "path_turn_hz", "path_pitch_hz", "encoder_jitter", "use_accel", "adapt",
    "guard_angle", "pendulum_range",
)


def _class_name(name: str) -> str:
    return "".join(p[:1].upper() + p[1:] for p in name.split("_"))


def _rig_with(rig: RigLike, table: Optional[str], settings: Dict[str, Any], kind: str) -> RigLike:
    if not settings:
        return rig
    if table is None:
        raise PendtiltError(f"no settings in the rig file for this estimator: {sorted(settings)}")
    if rig is None:
        r = Rig.default(kind)
    elif isinstance(rig, Rig):
        r = rig
    elif isinstance(rig, Mapping):
        r = Rig.from_dict(rig)
    else:
        r = read_rig(rig)
    return r.with_settings(table, **settings)


def _planar_class(name: str, about: str) -> type:
    table = _TABLE.get(name)

    class _One(Stream):
        def __init__(self, rig: RigLike = None, **settings: Any) -> None:
            super().__init__(_rig_with(rig, table, settings, "planar"), [name])

        def update(  # type: ignore[override]
            self, t: float, phi: float = _NAN, gyro: float = _NAN, ax: float = _NAN,
            ay: float = _NAN,
        ) -> float:
            """One sample (see :meth:`Stream.update`): this estimator's tilt [rad]."""
            return self._s.update(t, phi, gyro, ax, ay)[self.names.index(name)]

    _One.__name__ = _One.__qualname__ = _class_name(name)
    _One.__doc__ = _doc(name, about, table, "planar")
    return _One


def _spatial_class(name: str, about: str) -> type:
    table = _TABLE.get(name)

    class _One(Stream3d):
        def __init__(
            self, rig: RigLike = None, scenario: Optional[PathLike] = None, **settings: Any
        ) -> None:
            super().__init__(_rig_with(rig, table, settings, "3d"), scenario, [name])

        def update(  # type: ignore[override]
            self, t: float, phi_x: float, phi_y: float, gyro_x: float, gyro_y: float,
            gyro_z: float, ax: float, ay: float, az: float, speed: float = _NAN,
        ) -> Tuple[float, float]:
            """One sample (see :meth:`Stream3d.update`): this estimator's (roll, pitch)
            [rad]."""
            out = self._s.update(t, phi_x, phi_y, gyro_x, gyro_y, gyro_z, ax, ay, az, speed)
            return tuple(out[self.names.index(name)])  # type: ignore[return-value]

    _One.__name__ = _One.__qualname__ = _class_name(name)
    _One.__doc__ = _doc(name, about, table, "3d")
    return _One


def _doc(name: str, about: str, table: Optional[str], kind: str) -> str:
    head = f"``{name}``: {about}. One sample at a time ({'Stream' if kind == 'planar' else 'Stream3d'} with this estimator alone).\n\n"
    if table is None:
        return head + "Settings: none in the rig file (the estimator's defaults)."
    defaults = ""
    if kind == "planar":
        d = Rig.default().to_dict().get(table, {})
        defaults = ", ".join(f"{k}={v!r}" for k, v in d.items()) or (
            "none written, every figure derived from the rig's sensors; the keys: "
            + ", ".join(_KEYS_EKF)
        )
    else:
        d = Rig.default("3d").to_dict().get(table, {})
        defaults = ", ".join(f"{k}={v!r}" for k, v in d.items())
    return (
        head
        + f"Settings: keyword arguments set keys of the rig's ``[{table}]`` table (SI "
        + f"units), checked as a rig file is. Defaults: {defaults}."
    )


#: Every estimator: name -> (its streaming class, model "planar" or "3d", about).
ESTIMATORS: Dict[str, Tuple[type, str, str]] = {}
for _name, _model, _family, _reads, _about in _pendtilt.catalogue():
    _cls = _planar_class(_name, _about) if _model == "planar" else _spatial_class(_name, _about)
    globals()[_cls.__name__] = _cls
    ESTIMATORS[_name] = (_cls, _model, _about)
    __all__.append(_cls.__name__)
del _name, _model, _family, _reads, _about, _cls
