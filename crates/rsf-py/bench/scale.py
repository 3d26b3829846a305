"""Scaling of diagnose_many on a Dask LocalCluster: 1 worker against 2 (one thread each), the
same records, medians of --repeat runs, the tables compared. docs/scale.md has the numbers.

    target/pyvenv/bin/python crates/rsf-py/bench/scale.py MANIFEST.csv [--repeat 3] [--workers 1 2]
"""

import argparse
import statistics
import time

import distributed
import pandas as pd

import rsf


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("manifest")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    a = ap.parse_args()
    tables, medians = {}, {}
    for n in a.workers:
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster, distributed.Client(cluster) as c:
            walls = []
            for _ in range(a.repeat):
                t0 = time.perf_counter()
                tables[n] = rsf.diagnose_many(a.manifest, client=c)
                walls.append(time.perf_counter() - t0)
            medians[n] = statistics.median(walls)
            print(f"{n} worker(s): median {medians[n]:.1f} s of {a.repeat} ({', '.join(f'{w:.1f}' for w in walls)})",
                  flush=True)
    first = a.workers[0]
    for n in a.workers[1:]:
        pd.testing.assert_frame_equal(tables[n], tables[first])
        print(f"speed-up {first} -> {n} workers: {medians[first] / medians[n]:.2f}x; tables equal")


if __name__ == "__main__":
    main()
