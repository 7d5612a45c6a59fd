"""What Python costs on top of the library: a planar estimate of N rows (default 1M).

Times, best of --repeat runs each, on the same simulated scooter log:
  library   the Rust example `estimate_in_memory` (the library alone, as the package runs
            it: read the CSV, estimate, keep every estimate and flag in memory; its own
            wall time, process start-up left out): the figure Python is measured against;
  command   `pendtilt estimate LOG.csv --params RIG -o OUT.csv -q` (the same, with the
            estimates written as CSV);
  py-file   `pendtilt.estimate("LOG.csv", rig=RIG)` (the same read, estimates kept in
            NumPy arrays instead of written);
  py-arrays `pendtilt.estimate(columns, rig=RIG)` with the columns already in NumPy
            arrays (a DataFrame's): the table is handed to the reader as text.

    cargo build --release -p pendtilt --example estimate_in_memory
    python python/bench/overhead.py [--rows 1000000] [--repeat 3] [--bin target/release/pendtilt]
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
    ap.add_argument(
        "--library",
        default=str(target / "release" / "examples" / "estimate_in_memory"),
    )
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        sim = pendtilt.simulate("scooter", Path(d) / "ride.csv", duration=a.rows / 1000)
        columns = sim.data
        out = Path(d) / "est.csv"
        cmd = [a.bin, "estimate", str(sim.log), "--params", str(sim.rig), "-o", str(out), "-q"]
        lib = [a.library, str(sim.log), str(sim.rig)]

        def library() -> float:
            out = subprocess.run(lib, check=True, capture_output=True, text=True).stdout
            return float(out.split(",")[-1].split()[0])

        t_lib = min(library() for _ in range(a.repeat))
        t_cmd = best(lambda: subprocess.run(cmd, check=True), a.repeat)
        t_file = best(lambda: pendtilt.estimate(sim.log, rig=sim.rig), a.repeat)
        t_arr = best(lambda: pendtilt.estimate(columns, rig=sim.rig), a.repeat)
        n = len(columns["t"])
        est = pendtilt.estimate(columns, rig=sim.rig)
        print(f"{n} rows, {len(est.names)} estimators, best of {a.repeat}")
        runs = (("library", t_lib), ("command", t_cmd), ("py-file", t_file), ("py-arrays", t_arr))
        for name, t in runs:
            print(f"{name:<10} {t:7.3f} s  {t / t_lib - 1:+7.1%} vs the library alone")


if __name__ == "__main__":
    main()
