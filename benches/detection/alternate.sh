#!/usr/bin/env bash
# Paired wall times of two rsf builds (issues 22, 38): each record is diagnosed by NEW, OLD, NEW,
# OLD, NEW, OLD, so that both builds see the same machine state; prints one line per run
# (record, rows, truth, build, wall s, peak KB, the cause named). Summarise with
# benches/detection/alternate_table.py.
#   bash benches/detection/alternate.sh DIR NEW_RSF OLD_RSF > runs.txt
#       the records of a generated set (manifest.json) with 55,000–80,000 rows
#   bash benches/detection/alternate.sh DIR NEW_RSF OLD_RSF normal-stress > runs.txt
#       the records of benches/normal_stress/make_records.py (truth.json), σ read from their column
set -euo pipefail
dir=$1 new=$2 old=$3 kind=${4:-detection}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$dir" "$kind" > "$tmp/list" <<'PY'
import json, sys
if sys.argv[2] == "normal-stress":
    for r in json.load(open(sys.argv[1] + "/truth.json")):
        print(r["file"], r["params"]["k"], "normal_stress", r["n_samples"])
else:
    for r in json.load(open(sys.argv[1] + "/manifest.json")):
        if 55000 <= r["n_samples"] <= 80000:
            print(r["file"], r["nominal_stiffness"], r["cause"], r["n_samples"])
PY
extra=()
[ "$kind" = normal-stress ] && extra=(--lp-col lp_um --normal-col normal_stress_mpa)
while read -r f k c n; do
  for b in new old new old new old; do
    bin=$new; [ "$b" = old ] && bin=$old
    /usr/bin/time -o "$tmp/t" -f "%e %M" "$bin" diagnose "$dir/$f" "${extra[@]}" --stiffness "$k" > "$tmp/out" 2>/dev/null
    echo "$f $n $c $b $(tail -1 "$tmp/t") $(head -1 "$tmp/out")"
  done
done < "$tmp/list"
