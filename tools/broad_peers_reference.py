#!/usr/bin/env python3
"""Reference VQF, Madgwick and Mahony on the BROAD excerpt, for tests/broad_peers.rs.

Runs the reference filters of tools/broad_reference.py (the `vqf` package's real-time
VQF, the `ahrs` package's Madgwick and Mahony, all at their defaults, no magnetometer) on
each excerpt file of crates/pendtilt/tests/data/broad, from its first row, and writes
beside them:
  peers_reference_scores.csv  trial,filter,rms_deg,max_deg: the inclination error from
                              the optical truth over the scored rows (movement == 1 and
                              the truth finite), as broad_reference.py scores a trial;
  peers_reference_up.csv      trial,filter,row,ux,uy,uz: the filter's world up direction
                              in body axes at every 286th row and the last.

    python3 tools/broad_peers_reference.py [crates/pendtilt/tests/data/broad]

Made with python 3.11.7, numpy 2.4.6, scipy 1.17.1, vqf 2.1.2, ahrs 0.4.0 (the versions in
use are printed to stderr).
"""
import glob
import os
import sys
from importlib.metadata import version

import numpy as np
import scipy.io

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from broad_reference import angle_deg, run_filters, up_in_body  # noqa: E402

EVERY = 286


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else 'crates/pendtilt/tests/data/broad'
    vers = ', '.join(f'{p} {version(p)}' for p in ('numpy', 'scipy', 'vqf', 'ahrs'))
    print(f'# python {sys.version.split()[0]}, {vers}', file=sys.stderr)
    scores = ['trial,filter,rms_deg,max_deg']
    ups = ['trial,filter,row,ux,uy,uz']
    for path in sorted(glob.glob(os.path.join(folder, '[0-9][0-9]_*.mat'))):
        trial = os.path.basename(path)[:2]
        d = scipy.io.loadmat(path)
        fs = float(d['sampling_rate'].item())
        q_true = np.asarray(d['opt_quat'], dtype=np.float64)
        mask = (d['movement'].ravel() == 1) & ~np.isnan(q_true).any(axis=1)
        u_true = up_in_body(q_true[mask])
        n = len(q_true)
        rows = sorted(set(range(0, n, EVERY)) | {n - 1})
        for name, q in run_filters(d['imu_gyr'], d['imu_acc'], fs).items():
            u = up_in_body(q)
            e = angle_deg(u_true, u[mask])
            scores.append(f'{trial},{name},{np.sqrt(np.mean(e ** 2)):.10f},{e.max():.10f}')
            ups.extend(f'{trial},{name},{k},{u[k, 0]:.15f},{u[k, 1]:.15f},{u[k, 2]:.15f}'
                       for k in rows)
    for file, lines in (('peers_reference_scores.csv', scores), ('peers_reference_up.csv', ups)):
        with open(os.path.join(folder, file), 'w') as f:
            f.write('\n'.join(lines) + '\n')
    print('\n'.join(scores), file=sys.stderr)


if __name__ == '__main__':
    main()
