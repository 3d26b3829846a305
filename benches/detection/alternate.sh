#!/usr/bin/env bash
# Paired wall times of two rsf builds on the records of a generated set with 55,000–80,000 rows
# (issue 22): each record is diagnosed by NEW, OLD, NEW, OLD, NEW, OLD, so that both builds see
# the same machine state; prints one line per run (record, rows, truth, build, wall s, peak KB,
# the cause named). Summarise with benches/detection/alternate_table.py.
#   bash benches/detection/alternate.sh DIR NEW_RSF OLD_RSF > runs.txt
set -euo pipefail
dir=$1 new=$2 old=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$dir" > "$tmp/list" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1] + "/manifest.json")):
    if 55000 <= r["n_samples"] <= 80000:
        print(r["file"], r["nominal_stiffness"], r["cause"], r["n_samples"])
PY
while read -r f k c n; do
  for b in new old new old new old; do
    bin=$new; [ "$b" = old ] && bin=$old
    /usr/bin/time -o "$tmp/t" -f "%e %M" "$bin" diagnose "$dir/$f" --stiffness "$k" > "$tmp/out" 2>/dev/null
    echo "$f $n $c $b $(tail -1 "$tmp/t") $(head -1 "$tmp/out")"
  done
done < "$tmp/list"
