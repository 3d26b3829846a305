#!/usr/bin/env bash
# Work–precision diagrams of rsf's integrators beside scipy's (Radau, LSODA, DOP853) on four
# cases; run from the repository root:  bash benches/work_precision/run.sh [REPEATS]
# Needs python3 with numpy, scipy and matplotlib (PY=/path/to/python to choose one), e.g.
#   python3 -m venv /tmp/wpvenv && /tmp/wpvenv/bin/pip install numpy scipy matplotlib
#   PY=/tmp/wpvenv/bin/python bash benches/work_precision/run.sh
# Writes docs/figures/work_precision_<case>.svg and docs/figures/work_precision.md; the
# numbers quoted in docs/BENCHMARKS.md and docs/solvers.md come from this run.
set -euo pipefail
cd "$(dirname "$0")/../.."
PY=${PY:-python3}
REPEATS=${1:-5}
OUT=${WP_OUT:-target/work_precision}
cargo build --release -q -p rsf-solvers --example work_precision
target/release/examples/work_precision "$OUT" --repeats "$REPEATS"
pairs=()
for c in seed hold stickslip two_state; do
  "$PY" benches/work_precision/peers.py "$OUT/$c.json" "$OUT/${c}_peers.json" --repeats "$REPEATS"
  pairs+=("$OUT/${c}_rsf.json" "$OUT/${c}_peers.json")
done
"$PY" benches/work_precision/plot.py docs/figures "${pairs[@]}"
# the whole `rsf simulate` process (start, TOML, solve, CSV) on the seed-like protocol of 71
# segments with output every 50 s (rtol 1e-8, atol 1e-12, method auto), beside /bin/true (the
# machine's process floor) in the same go, against scipy Radau's solve of the same protocol at
# rtol 1e-8 from the peers run above. Timed two ways, medians of 101 runs: by hyperfine -N
# (the usual tool for timing commands; `apt-get install hyperfine`; skipped when absent), and
# around Python's subprocess.run, where the interpreter's own work between runs evicts rsf
# from the CPU caches (0.1–0.2 ms slower: a process started from a notebook). A `$(date)` pair
# in bash would add two forks, about 1 ms.
# Timed as installed (`install`, as `cargo install` copies it): a binary the linker has just
# written sits in the page cache in small pieces and starts 0.1–0.15 ms slower until the cache
# is refilled (measured here; the same file after `echo 1 > /proc/sys/vm/drop_caches`, or any
# copy, starts at the installed speed).
cargo build --release -q -p rsf-cli
install -m 755 target/release/rsf "$OUT/rsf"
SIM="$OUT/rsf simulate $OUT/seed.toml -o $OUT/seed.csv"
if command -v hyperfine > /dev/null; then
  hyperfine -N --warmup 20 --runs 101 --export-json "$OUT/process_hyperfine.json" "$SIM" /bin/true > /dev/null
fi
"$PY" - "$OUT" <<'PYEOF'
import json, os, statistics, subprocess, sys, time
out = sys.argv[1]
def median_ms(cmd, n=101):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        ts.append(time.perf_counter() - t)
    return statistics.median(ts) * 1e3
rsf = median_ms([f"{out}/rsf", "simulate", f"{out}/seed.toml", "-o", f"{out}/seed.csv"])
floor = median_ms(["/bin/true"])
runs = json.load(open(f"{out}/seed_peers.json"))["runs"]
radau = [r for r in runs if r["method"] == "Radau" and abs(r["rtol"] - 1e-8) < 1e-20 and "wall_s" in r][0]["wall_s"]
open(f"{out}/process_ms.txt", "w").write(f"{rsf:.3f} {floor:.3f}\n")
print(f"scipy Radau solve at rtol 1e-8: {radau * 1e3:.0f} ms")
hf = f"{out}/process_hyperfine.json"
if os.path.exists(hf):
    r = json.load(open(hf))["results"]
    print(f"rsf simulate process, hyperfine -N, median of 101: {r[0]['median'] * 1e3:.2f} ms "
          f"(/bin/true {r[1]['median'] * 1e3:.2f} ms); ratio {radau / r[0]['median']:.0f}x")
print(f"rsf simulate process, Python subprocess.run, median of 101: {rsf:.2f} ms (/bin/true {floor:.2f} ms); "
      f"ratio {radau * 1e3 / rsf:.0f}x")
PYEOF
