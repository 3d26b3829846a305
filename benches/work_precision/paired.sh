#!/usr/bin/env bash
# The whole `rsf simulate` process against scipy Radau's solve, measured in alternation so that
# both see the same machine load (on a shared VM the same binary moves by ±10 % over minutes):
# ROUNDS times (default 4), hyperfine -N (median of 51 runs) of the installed `rsf simulate` on
# the seed-like protocol, then one scipy Radau solve of the same protocol at rtol 1e-8
# (benches/scipy_protocol.py). Prints each round's ratio and their median.
# Needs: a prior `bash benches/work_precision/run.sh` (for target/work_precision/seed.toml and
# the installed binary), hyperfine, and python with numpy and scipy (PY=...).
set -euo pipefail
cd "$(dirname "$0")/../.."
PY=${PY:-python3}
ROUNDS=${1:-4}
OUT=${WP_OUT:-target/work_precision}
cargo run --release -q -p rsf-solvers --example bench_protocol -- --repeats 1 --no-scipy > /dev/null
JSON="$(${PY} -c 'import tempfile; print(tempfile.gettempdir())')/rsf_bench_protocol.json"
test -f "$JSON" || { echo "no $JSON: bench_protocol writes it"; exit 1; }
for r in $(seq "$ROUNDS"); do
  hyperfine -N --warmup 10 --runs 51 --export-json "$OUT/paired_$r.json" \
    "$OUT/rsf simulate $OUT/seed.toml -o $OUT/seed.csv" > /dev/null 2>&1
  "$PY" benches/scipy_protocol.py "$JSON" --repeats 1 > "$OUT/paired_radau_$r.json"
done
"$PY" - "$OUT" "$ROUNDS" <<'PYEOF'
import json, statistics, sys
out, n = sys.argv[1], int(sys.argv[2])
ratios = []
for r in range(1, n + 1):
    rsf = json.load(open(f"{out}/paired_{r}.json"))["results"][0]["median"]
    radau = json.load(open(f"{out}/paired_radau_{r}.json"))["wall_s_median"]
    ratios.append(radau / rsf)
    print(f"round {r}: rsf simulate process {rsf * 1e3:.2f} ms, scipy Radau solve {radau * 1e3:.0f} ms, ratio {radau / rsf:.0f}x")
print(f"median ratio {statistics.median(ratios):.0f}x")
PYEOF
