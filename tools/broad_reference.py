#!/usr/bin/env python3
"""Reference inclination errors of off-the-shelf 6D orientation filters on BROAD.

For every BROAD trial file (NN_*.mat) this runs, with default parameters and
without magnetometer:
  * VQF      -- `vqf` package, real-time `VQF(Ts)` class, `updateBatch(...)['quat6D']`
  * Madgwick -- `ahrs.filters.Madgwick(gyr, acc, frequency=fs)` (default gain_imu 0.033)
  * Mahony   -- `ahrs.filters.Mahony(gyr, acc, frequency=fs)` (defaults k_P=1.0, k_I=0.3)
and compares them with the optical truth `opt_quat` (w,x,y,z; world(ENU) <- IMU).

Initialisation: VQF starts from identity and converges via its initial
fast accelerometer low-pass. ahrs Madgwick and Mahony (6D, no q0 given) start
from `acc2q(acc[0])` (roll/pitch from the first accelerometer sample, yaw 0), so
their inclination is roughly right from sample 0. Note that both ahrs filters
skip the whole update (including the accelerometer correction) on samples where
the gyro reading is exactly zero.

Inclination error per sample: u = R(q)^T e_z (world up in body axes) for the
estimate and the truth; e_inc = atan2(|u_true x u_est|, u_true . u_est).
It does not depend on heading. Scored samples: movement == 1 and truth not NaN.
We report RMS and max, both over all scored samples and over those whose true
tilt (angle between u_true and e_z) is < 60 deg.

Dataset: D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD -- A Benchmark for
Robust Inertial Orientation Estimation", Data 6(7), 2021, CC-BY 4.0.

Run with: python 3.11.7, numpy 2.4.6, scipy 1.17.1, vqf 2.1.2, ahrs 0.4.0
(the versions in use are printed to stderr at every run).

Usage: broad_reference.py [DIR] [-o OUT.csv]     (DIR defaults to /tmp/broad)
"""
import argparse
import glob
import os
import sys
from importlib.metadata import version

import numpy as np
import scipy.io
from ahrs.filters import Madgwick, Mahony
from vqf import VQF


def up_in_body(q):
    """World z axis expressed in body axes, R(q)^T e_z, for q = (w,x,y,z) world <- body."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)


def angle_deg(a, b):
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1)))


def run_filters(gyr, acc, fs):
    gyr = np.ascontiguousarray(gyr, dtype=np.float64)
    acc = np.ascontiguousarray(acc, dtype=np.float64)
    return {
        'vqf': VQF(1.0 / fs).updateBatch(gyr, acc)['quat6D'],
        'madgwick': Madgwick(gyr=gyr, acc=acc, frequency=fs).Q,
        'mahony': Mahony(gyr=gyr, acc=acc, frequency=fs).Q,
    }


def rms_max(e):
    return (float(np.sqrt(np.mean(e ** 2))), float(np.max(e))) if e.size else (np.nan, np.nan)


def evaluate(path):
    d = scipy.io.loadmat(path)
    fs = float(d['sampling_rate'].item())
    q_true = np.asarray(d['opt_quat'], dtype=np.float64)
    mask = (d['movement'].ravel() == 1) & ~np.isnan(q_true).any(axis=1)
    u_true = up_in_body(q_true[mask])
    tilt = angle_deg(u_true, np.array([[0.0, 0.0, 1.0]]))
    low = tilt < 60.0
    rows = []
    for name, q_est in run_filters(d['imu_gyr'], d['imu_acc'], fs).items():
        e = angle_deg(u_true, up_in_body(q_est[mask]))
        rows.append(dict(filter=name, fs=fs, n=int(mask.sum()), n60=int(low.sum()),
                         max_tilt_deg=float(tilt.max()) if tilt.size else np.nan,
                         **dict(zip(('rms_deg', 'max_deg'), rms_max(e))),
                         **dict(zip(('rms60_deg', 'max60_deg'), rms_max(e[low])))))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('dir', nargs='?', default='/tmp/broad')
    ap.add_argument('-o', '--out', default='-')
    args = ap.parse_args()
    vers = ', '.join(f'{p} {version(p)}' for p in ('numpy', 'scipy', 'vqf', 'ahrs'))
    print(f'# python {sys.version.split()[0]}, {vers}', file=sys.stderr)

    cols = ['rms_deg', 'max_deg', 'rms60_deg', 'max60_deg', 'n', 'n60', 'max_tilt_deg']
    lines = ['trial,filter,' + ','.join(cols)]
    table = {}
    for path in sorted(glob.glob(os.path.join(args.dir, '[0-9][0-9]_*.mat'))):
        trial = os.path.basename(path)[:2]
        for r in evaluate(path):
            lines.append(f'{trial},{r["filter"]},' + ','.join(
                str(r[c]) if c in ('n', 'n60') else f'{r[c]:.4f}' for c in cols))
            table.setdefault(trial, {'fs': r['fs'], 'tilt': r['max_tilt_deg'], 'n': r['n']})[r['filter']] = r

    out = sys.stdout if args.out == '-' else open(args.out, 'w')
    out.write('\n'.join(lines) + '\n')
    if out is not sys.stdout:
        out.close()

    names = ['vqf', 'madgwick', 'mahony']
    print('trial   fs[Hz]      n  maxtilt | RMS (max) [deg]: ' + '   '.join(f'{n:>14}' for n in names),
          file=sys.stderr)
    for trial, t in table.items():
        cells = '   '.join(f'{t[n]["rms_deg"]:6.2f} ({t[n]["max_deg"]:6.2f})' for n in names)
        print(f'{trial:>5} {t["fs"]:8.2f} {t["n"]:6d} {t["tilt"]:8.1f} |                  {cells}',
              file=sys.stderr)


if __name__ == '__main__':
    main()
