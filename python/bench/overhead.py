"""What Python costs on top of the library: a planar estimate of N rows (default 1M).

Times, best of --repeat runs each, on the same simulated scooter log:
  command   `pendtilt estimate LOG.csv --params RIG -o OUT.csv -q` (the library alone,
            as the command runs it: read the CSV, estimate, write the CSV);
  py-file   `pendtilt.estimate("LOG.csv", rig=RIG)` (the same read, estimates kept in
            NumPy arrays instead of written);
  py-arrays `pendtilt.estimate(columns, rig=RIG)` with the columns already in NumPy
            arrays (a DataFrame's): the table is handed to the reader as text.

    python bench/overhead.py [--rows 1000000] [--repeat 3] [--bin target/release/pendtilt]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import tempfile
import time
from pathlib import Path

import pendtilt


def best(f, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=3)
    target = Path(os.environ.get("CARGO_TARGET_DIR", "target"))
    ap.add_argument("--bin", default=str(target / "release" / "pendtilt"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        sim = pendtilt.simulate("scooter", Path(d) / "ride.csv", duration=a.rows / 1000)
        columns = sim.data
        out = Path(d) / "est.csv"
        cmd = [a.bin, "estimate", str(sim.log), "--params", str(sim.rig), "-o", str(out), "-q"]
        t_cmd = best(lambda: subprocess.run(cmd, check=True), a.repeat)
        t_file = best(lambda: pendtilt.estimate(sim.log, rig=sim.rig), a.repeat)
        t_arr = best(lambda: pendtilt.estimate(columns, rig=sim.rig), a.repeat)
        n = len(columns["t"])
        est = pendtilt.estimate(columns, rig=sim.rig)
        print(f"{n} rows, {len(est.names)} estimators, best of {a.repeat}")
        for name, t in (("command", t_cmd), ("py-file", t_file), ("py-arrays", t_arr)):
            print(f"{name:<10} {t:7.3f} s  {t / t_cmd - 1:+7.1%} vs the command")


if __name__ == "__main__":
    main()
