"""The whole `rsf simulate` process of two builds, timed in alternation (same machine load):
output to /dev/null, to a new file, and over an existing file, beside /bin/true.

    python3 benches/process_timing.py BEFORE_BINARY AFTER_BINARY PROTOCOL.toml [RUNS]

PROTOCOL.toml: e.g. target/work_precision/seed.toml (written by benches/work_precision/run.sh,
or by `target/release/examples/work_precision DIR --repeats 1`). Prints medians in ms. Copy the
binaries somewhere first (`install -m 755`): a binary the linker has just written starts slower
until the page cache is refilled.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time


def main():
    before, after, protocol = sys.argv[1:4]
    runs = int(sys.argv[4]) if len(sys.argv) > 4 else 61
    out = tempfile.mkdtemp()
    fresh = os.path.join(out, "new.csv")

    def drop_fresh():
        if os.path.exists(fresh):
            os.unlink(fresh)

    cases = {
        "before -o /dev/null": ([before, "simulate", protocol, "-o", "/dev/null"], None),
        "after -o /dev/null": ([after, "simulate", protocol, "-o", "/dev/null"], None),
        "before -o existing file": ([before, "simulate", protocol, "-o", os.path.join(out, "b.csv")], None),
        "after -o existing file": ([after, "simulate", protocol, "-o", os.path.join(out, "a.csv")], None),
        "after -o new file": ([after, "simulate", protocol, "-o", fresh], drop_fresh),
        "/bin/true": (["/bin/true"], None),
    }
    times = {k: [] for k in cases}
    for r in range(runs + 5):
        for k, (cmd, pre) in cases.items():
            if pre:
                pre()
            t = time.perf_counter()
            subprocess.run(cmd, stderr=subprocess.DEVNULL, check=True)
            if r >= 5:  # warm-up rounds are not counted
                times[k].append(time.perf_counter() - t)
    for k, v in times.items():
        print(f"{k}: median {statistics.median(v) * 1e3:.3f} ms ({len(v)} runs)")


if __name__ == "__main__":
    main()
