#!/usr/bin/env python3
"""Cut the BROAD excerpt that pendtilt's tests replay (crates/pendtilt/tests/data/broad).

Each excerpt is 40 s of one trial: the last 8 s of its initial rest and the first 32 s of
its movement phase, with the variables the replay reads (imu_gyr, imu_acc, opt_quat as
float32; movement; sampling_rate), written as a compressed MATLAB v5 file.

    python3 tools/broad_excerpt.py BROAD/data_mat crates/pendtilt/tests/data/broad

Data: D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD - A Benchmark for Robust Inertial
Orientation Estimation", Data 6(7), 2021, doi:10.3390/data6070072; CC-BY 4.0.
"""
import sys
from pathlib import Path

import numpy as np
import scipy.io as sio

TRIALS = [
    "06_undisturbed_fast_rotation_A",
    "10_undisturbed_slow_translation_A",
    "16_undisturbed_fast_translation_B",
    "24_disturbed_tapping_A",
    "27_disturbed_phone_vibration_B",
]
REST_S, MOVE_S = 8, 32


def main(src: Path, dst: Path) -> None:
    dst.mkdir(parents=True, exist_ok=True)
    for name in TRIALS:
        d = sio.loadmat(src / f"{name}.mat")
        fs = d["sampling_rate"].item()
        first = int(np.argmax(d["movement"].ravel() > 0))
        a, b = max(0, first - int(REST_S * fs)), first + int(MOVE_S * fs)
        out = {k: d[k][a:b].astype(np.float32) for k in ("imu_gyr", "imu_acc", "opt_quat")}
        out["movement"] = d["movement"][a:b]
        out["sampling_rate"] = d["sampling_rate"]
        sio.savemat(dst / f"{name}.mat", out, do_compression=True)
        print(f"{name}: rows {a}..{b} of {len(d['movement'])}")


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
