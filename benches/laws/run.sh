#!/usr/bin/env bash
# The cost of a law by its form (docs/BENCHMARKS.md, "Laws written three ways"). Run from the
# repository root after `cargo build --release -p rsf-cli` and `bash crates/rsf-py/test.sh`.
set -euo pipefail
R=target/release/rsf
echo "== rsf simulate: in-process solve time (ms), 21 runs each, alternated"
for method in rodas5p auto; do
    for i in $(seq 1 21); do
        for f in builtin text power; do
            $R simulate benches/laws/steps_$f.toml -o /dev/null --method $method 2>&1 |
                sed -n "s/.*solve \([0-9.]*\) ms.*/$method $f \1/p"
        done
    done
done | python3 -c '
import statistics, sys
d = {}
for line in sys.stdin:
    m, f, v = line.split(); d.setdefault((m, f), []).append(float(v))
for (m, f), v in sorted(d.items()):
    print(f"{m:8} {f:8} median {statistics.median(v):.3f} ms  x{statistics.median(v) / statistics.median(d[(m, \"builtin\")]):.2f}")'
echo "== rsf fit, whole process: law file (A) against built in (B)"
farm-bench -n 9 --vs "$R fit tests/data/outside/power_aging.csv --law aging --stiffness 0.02" -- \
    $R --law-file benches/laws/aging_text.toml fit tests/data/outside/power_aging.csv --law aging-text --stiffness 0.02
echo "== Python"
target/pyvenv/bin/python benches/laws/python_laws.py
