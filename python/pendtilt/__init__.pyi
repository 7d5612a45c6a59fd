"""Type stubs of the pendtilt package (see the module's docstrings)."""
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Type, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, "os.PathLike[str]"]
RigLike = Union[None, PathLike, "Rig", Mapping[str, Any]]
__version__: str

class PendtiltError(ValueError):
    """An error of pendtilt, with the message the command prints after `error: `."""

def library_version() -> str: ...
def run(*args: str) -> None: ...
def catalogue() -> List[Dict[str, Any]]: ...
def flag_names(bits: int) -> str: ...

class Rig:
    kind: str
    text: str
    canonical: str
    doubts: List[str]
    def __init__(self, text: str, origin: str = ...) -> None: ...
    @classmethod
    def default(cls, kind: str = ...) -> "Rig": ...
    @classmethod
    def from_dict(cls, tables: Mapping[str, Mapping[str, Any]]) -> "Rig": ...
    def to_dict(self) -> Dict[str, Dict[str, Any]]: ...
    def to_toml(self) -> str: ...
    def with_settings(self, table: str, **values: Any) -> "Rig": ...

def read_rig(path: PathLike) -> Rig: ...
def write_rig(rig: Union[Rig, Mapping[str, Any]], path: PathLike) -> None: ...
def read_csv(path: PathLike) -> Dict[str, Any]: ...
def write_csv(data: Any, path: PathLike) -> None: ...

class Estimates:
    model: str
    names: List[str]
    rows: int
    warnings: List[str]
    warning_count: int
    notes: List[str]
    flags: Dict[str, npt.NDArray[np.uint16]]
    errors: Optional[Dict[str, Tuple[float, float, int, int]]]
    scores: Optional[Dict[str, Tuple[float, float, float, int, int]]]
    score_from: Optional[float]
    columns: Dict[str, npt.NDArray[np.float64]]
    @property
    def rms(self) -> Dict[str, float]: ...
    def error_table(self) -> Optional[str]: ...
    def __getitem__(self, name: str) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...
    def flag_texts(self, name: str) -> List[str]: ...
    def to_dict(self, flags: Optional[bool] = ...) -> Dict[str, Any]: ...
    def to_pandas(self, flags: Optional[bool] = ...) -> Any: ...

def estimate(
    data: Any,
    rig: RigLike = ...,
    *,
    scenario: Optional[PathLike] = ...,
    only: Optional[Union[str, Sequence[str]]] = ...,
    map: Optional[Union[str, Mapping[str, str]]] = ...,
    deg: Union[None, bool, str, Sequence[str]] = ...,
    time_unit: Optional[str] = ...,
    accel_unit: Optional[str] = ...,
    negate: Optional[Union[str, Sequence[str]]] = ...,
    flags: bool = ...,
    out_deg: bool = ...,
    quaternion: bool = ...,
    score_from: Optional[float] = ...,
    name: Optional[str] = ...,
) -> Estimates: ...

class Simulation:
    log: os.PathLike[str]
    rig: os.PathLike[str]
    scenario: Optional[os.PathLike[str]]
    @property
    def data(self) -> Dict[str, Any]: ...
    def to_pandas(self) -> Any: ...
    def read_rig(self) -> Rig: ...

def simulate(
    scenario: str = ...,
    output: Optional[PathLike] = ...,
    *,
    seed: Optional[int] = ...,
    duration: Optional[float] = ...,
    rig: RigLike = ...,
    quiet: bool = ...,
    **options: Any,
) -> Simulation: ...
def replay(
    imu: Any, output: Optional[PathLike] = ..., *, params: RigLike = ..., quiet: bool = ...,
    **options: Any,
) -> Simulation: ...
def fit(
    log: Any, output: Optional[PathLike] = ..., *, params: RigLike = ..., quiet: bool = ...,
    **options: Any,
) -> Rig: ...
def tune(
    log: Any, output: Optional[PathLike] = ..., *, params: RigLike = ..., quiet: bool = ...,
    **options: Any,
) -> Rig: ...

class Stream:
    names: List[str]
    def __init__(
        self, rig: RigLike = ..., estimators: Optional[Sequence[str]] = ...,
        sensors: Sequence[str] = ...,
    ) -> None: ...
    def update(
        self, t: float, phi: float = ..., gyro: float = ..., ax: float = ..., ay: float = ...
    ) -> Dict[str, float]: ...
    def flags(self) -> Dict[str, int]: ...
    def update_many(
        self, t: Any, phi: Any = ..., gyro: Any = ..., ax: Any = ..., ay: Any = ...
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint16]]: ...
    def reset(self) -> None: ...

class Stream3d:
    names: List[str]
    def __init__(
        self, rig: RigLike = ..., scenario: Optional[PathLike] = ...,
        estimators: Optional[Sequence[str]] = ...,
    ) -> None: ...
    def update(
        self, t: float, phi_x: float, phi_y: float, gyro_x: float, gyro_y: float,
        gyro_z: float, ax: float, ay: float, az: float, speed: float = ...,
    ) -> Dict[str, Tuple[float, float]]: ...
    def flags(self) -> Dict[str, int]: ...
    def quaternion(self, name: str) -> Optional[Tuple[float, float, float, float]]: ...

class _Planar(Stream):
    def __init__(self, rig: RigLike = ..., **settings: Any) -> None: ...
    def update(  # type: ignore[override]
        self, t: float, phi: float = ..., gyro: float = ..., ax: float = ..., ay: float = ...
    ) -> float: ...

class _Spatial(Stream3d):
    def __init__(
        self, rig: RigLike = ..., scenario: Optional[PathLike] = ..., **settings: Any
    ) -> None: ...
    def update(  # type: ignore[override]
        self, t: float, phi_x: float, phi_y: float, gyro_x: float, gyro_y: float,
        gyro_z: float, ax: float, ay: float, az: float, speed: float = ...,
    ) -> Tuple[float, float]: ...

ESTIMATORS: Dict[str, Tuple[Type[Stream], str, str]]

# One class per estimator (pendtilt.catalogue()).
class Accel(_Planar):
    """``accel``: accelerometer, Eq (1)."""

class Pendulum(_Planar):
    """``pendulum``: raw pendulum angle."""

class Alg1(_Planar):
    """``alg1``: Algorithm 1, Eq (20)."""

class Alg2(_Planar):
    """``alg2``: Algorithm 2, Eqs (21)-(22)."""

class Alg2Offset(_Planar):
    """``alg2_offset``: Algorithm 2 with the pivot-offset term (not in the paper)."""

class Alg2Dc(_Planar):
    """``alg2_dc``: Algorithm 2 with the differentiator's delay removed by the gyro (not in the paper)."""

class Alg3(_Planar):
    """``alg3``: Algorithm 3's Eq (30) with the configured K, L, M, N."""

class KfAccel(_Planar):
    """``kf_accel``: Kalman filter fed by the accelerometer (the classic filter)."""

class KfAlg1(_Planar):
    """``kf_alg1``: Kalman filter fed by Algorithm 1."""

class KfAlg2(_Planar):
    """``kf_alg2``: Kalman filter fed by Algorithm 2."""

class KfAlg3(_Planar):
    """``kf_alg3``: Kalman filter fed by Algorithm 3."""

class KfFused(_Planar):
    """``kf_fused``: Kalman filter fed by the accelerometer and Algorithm 2 in turn."""

class Ekf(_Planar):
    """``ekf``: EKF on the pendulum's own dynamics with l12 (the paper's future work)."""

class Ukf(_Planar):
    """``ukf``: UKF on the same model."""

class Madgwick(_Planar):
    """``madgwick``: Madgwick (ahrs crate), planar use, gain from a search on the scooter ride."""

class Mahony(_Planar):
    """``mahony``: Mahony (ahrs crate), planar use, gains from a search on the scooter ride."""

class Complementary(_Planar):
    """``complementary``: complementary filter of gyro and accelerometer."""

class Pendulum3d(_Spatial):
    """``pendulum3d``: raw encoder angles: roll = phi_x, pitch = phi_y."""

class Accel3d(_Spatial):
    """``accel3d``: roll and pitch of the accelerometer."""

class Inv3d(_Spatial):
    """``inv3d``: Algorithm 2 in three dimensions."""

class Ekf3d(_Spatial):
    """``ekf3d``: quaternion EKF with the pendulum's equations of motion."""

class Ukf3d(_Spatial):
    """``ukf3d``: the same model on the UKF."""

class Imu3d(_Spatial):
    """``imu3d``: ekf3d's filter with the accelerometer in place of the encoders (the ablation)."""

class Vqf(_Spatial):
    """``vqf``: VQF 6D (peer, vqf-rs)."""

class Madgwick3d(_Spatial):
    """``madgwick3d``: Madgwick IMU filter (peer, ahrs)."""

class Mahony3d(_Spatial):
    """``mahony3d``: Mahony IMU filter (peer, ahrs)."""

class Fusion3d(_Spatial):
    """``fusion3d``: Fusion-style complementary filter with acceleration rejection (peer)."""
