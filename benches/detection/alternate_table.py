"""Summarises benches/detection/alternate.sh: per record the median of each build's three runs
and their ratio, then the medians, the maxima and the peak memory (Markdown).

    python3 benches/detection/alternate_table.py runs.txt
"""

import collections
import statistics
import sys


def main():
    runs = collections.defaultdict(lambda: {"new": [], "old": [], "mem": []})
    meta = {}
    for line in open(sys.argv[1]):
        t = line.split()
        if len(t) < 7:
            continue
        f, n, truth, build, wall, mem = t[0], int(t[1]), t[2], t[3], float(t[4]), int(t[5])
        runs[f][build].append(wall)
        runs[f]["mem"].append(mem)
        m = meta.setdefault(f, {"rows": n, "truth": truth})
        m[build] = " ".join(t[6:]).removeprefix("cause: ")
    print("| record | rows | truth | named (now / before) | before (median of 3) | now (median of 3) | runs now | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    before, now = [], []
    for f in sorted(runs):
        r, m = runs[f], meta[f]
        o, n = statistics.median(r["old"]), statistics.median(r["new"])
        before.append(o)
        now.append(n)
        listed = ", ".join(f"{x:.1f}" for x in r["new"])
        print(f"| {f.removesuffix('.csv')} | {m['rows']:,} | {m['truth']} | {m.get('new')} / {m.get('old')} "
              f"| {o:.1f} s | **{n:.1f} s** | {listed} | {n / o:.2f} |")
    mb, mn = statistics.median(before), statistics.median(now)
    print(f"| **median** | | | | {mb:.1f} s | **{mn:.1f} s** | | **{mn / mb:.2f}** |")
    peak = max(max(r["mem"]) for r in runs.values()) / 1024
    print(f"\nmax now {max(now):.1f} s, before {max(before):.1f} s; peak memory {peak:.0f} MB")


if __name__ == "__main__":
    main()
