#!/usr/bin/env bash
# Large-record fits: `rsf fit` on 1M and 10M rows at 1 kHz, on bin means (default) and on every
# sample (--every-sample: the computation before bins), medians of 3 runs with peak memory.
# Usage: bash benches/large_fit/run.sh [DIR]   (DIR: where the records are made; default /tmp/rsf-large)
# Needs python3 with numpy and pandas (target/pyvenv from crates/rsf-py/test.sh has them).
set -euo pipefail
cd "$(dirname "$0")/../.."
D=${1:-/tmp/rsf-large}
PY=${PY:-target/pyvenv/bin/python}
mkdir -p "$D"
cargo build --release -q -p rsf-cli
R=target/release/rsf
for n in 1m 10m; do
  [ -f "$D/r$n.csv" ] && continue
  dt=$([ $n = 1m ] && echo 0.001 || echo 0.0001)
  sed "s/^dt = .*/dt = $dt/" benches/large_fit/protocol.toml > "$D/p$n.toml"
  "$R" simulate "$D/p$n.toml" -o "$D/sim$n.csv" 2>/dev/null
  "$PY" - "$D/sim$n.csv" "$D/r$n.csv" <<'PYEOF'
import sys, numpy as np, pandas as pd
d = pd.read_csv(sys.argv[1], usecols=["time_s", "load_point_um", "mu"])
d["mu"] += 1e-4 * np.random.default_rng(1).standard_normal(len(d))   # white noise, σ = 1e-4
d.to_csv(sys.argv[2], index=False, float_format="%.9g")
PYEOF
  rm -f "$D/sim$n.csv"
done
run() { # label, then the fit's arguments: median wall and peak RSS of 3 runs
  local label=$1; shift
  local walls=() mems=()
  for _ in 1 2 3; do
    /usr/bin/time -f "%e %M" -o "$D/time" "$R" fit "$@" --law slip --stiffness 0.01 --fit-stiffness > "$D/out.txt" 2>/dev/null
    read -r w m < "$D/time"; walls+=("$w"); mems+=("$m")
  done
  local a=$(grep -E "^ +a " "$D/out.txt" | awk '{print $2, $3}')
  printf '%-40s median %6.2f s  (%s)  peak %5d MB  a = %s\n' "$label" \
    "$(printf '%s\n' "${walls[@]}" | sort -n | sed -n 2p)" "${walls[*]}" \
    "$(( $(printf '%s\n' "${mems[@]}" | sort -n | tail -1) / 1024 ))" "$a"
}
for lm in record protocol; do
  run "1M rows, $lm loading, bins" "$D/r1m.csv" --loading $lm
  run "1M rows, $lm loading, --every-sample" "$D/r1m.csv" --loading $lm --every-sample
  run "10M rows, $lm loading, bins" "$D/r10m.csv" --loading $lm
done
