#!/usr/bin/env bash
# QDYN on rsf's friction: takes a QDYN checkout, makes a patched copy whose friction module is
# rsf's (crates/rsf-capi/qdyn/friction.f90 over QDYN's src/friction.f90, rsf's Fortran module
# include/rsf.f90 beside it, linked against librsf_capi.a), builds it, and runs QDYN's own
# unit tests (`qdyn test`) and regression suite (test/test_suite.py). With --compare, an
# unpatched copy is built and run the same way in the same go, for the timings. With --bp1,
# both run SEAS BP1-QD (bp1.py) and rsf-cycle runs it too.
#
#   bash crates/rsf-capi/qdyn/run.sh QDYN_DIR [--work DIR] [--python PY] [--compare]
#        [--bp1 CELLS,YEARS] [--no-suite] [--prefix DIR]
#
# QDYN_DIR: a QDYN checkout (git clone https://github.com/ydluo/qdyn, or the search tool's
# fetch); it is only read. Needs mpif90 (QDYN's Makefile; Debian: libopenmpi-dev openmpi-bin)
# and, for the suite, a Python with numpy, scipy, matplotlib, termcolor and pandas < 3 (QDYN's
# pyqdyn passes read_csv an argument pandas 3 removed). Exit status: 0 when every test passed
# (with --compare: when every case that passes on QDYN's own friction here passes on rsf's
# too), 1 when one failed, 2 on a usage error or a checkout this script cannot patch.
# QDYN's source never enters this repository, and nothing is written into it: the copies live
# under --work (default ${TMPDIR:-/tmp}/rsf-qdyn). QDYN links rsf as installed: from --prefix
# (an earlier `make install PREFIX=DIR`, found through its pkg-config file; no Rust needed), or
# else this checkout is installed first into WORK/prefix (`make install`, which runs cargo).
# Times on the machine of docs/faultsim.md: unit tests alone (--no-suite) 1 min with the
# builds; --compare 20 min; --compare --bp1 512,3000 about 30 min more.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"

usage() { sed -n '9,10p' "$0" >&2; exit 2; }
[ $# -ge 1 ] || usage
qdyn="$1"; shift
work="${TMPDIR:-/tmp}/rsf-qdyn"; py="${PYTHON:-python3}"; compare=0; bp1=""; suite=1; prefix=
while [ $# -gt 0 ]; do
  case "$1" in
    --work) work="$2"; shift 2 ;;
    --python) py="$2"; shift 2 ;;
    --compare) compare=1; shift ;;
    --bp1) bp1="$2"; shift 2 ;;
    --no-suite) suite=0; shift ;;
    --prefix) prefix="$2"; shift 2 ;;
    *) echo "run.sh: unknown option $1" >&2; usage ;;
  esac
done

# the checkout must have the friction module this client replaces, with its public interface
if [ ! -f "$qdyn/src/friction.f90" ] || [ ! -f "$qdyn/src/Makefile" ] || [ ! -d "$qdyn/test" ]; then
  echo "run.sh: $qdyn is not a QDYN checkout (no src/friction.f90, src/Makefile or test/)" >&2
  exit 2
fi
for routine in set_theta_star friction_mu dmu_dv_dtheta dtheta_dt; do
  if ! grep -q "public.*$routine" "$qdyn/src/friction.f90"; then
    echo "run.sh: $qdyn/src/friction.f90 does not make $routine public: its interface is not the one this client replaces" >&2
    exit 2
  fi
done
fc="${FC:-mpif90}"
if ! command -v "$fc" > /dev/null; then
  echo "run.sh: $fc not found (QDYN builds with MPI's Fortran wrapper; Debian: apt-get install libopenmpi-dev openmpi-bin)" >&2
  exit 2
fi
commit="$(git -C "$qdyn" rev-parse HEAD 2> /dev/null || git --git-dir="$qdyn/.git" rev-parse HEAD 2> /dev/null || echo unknown)"
echo "QDYN checkout: $qdyn (commit $commit)"

mkdir -p "$work"
if [ -z "$prefix" ]; then
  prefix="$work/prefix"
  echo "== rsf installed into $prefix (make install; its cargo build goes to $work/cargo-target)"
  make -s -C "$root" install PREFIX="$prefix" TARGET_DIR="$work/cargo-target" > "$work/install.log" 2>&1 \
    || { tail -20 "$work/install.log" >&2; echo "run.sh: make install failed (log: $work/install.log)" >&2; exit 2; }
fi
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
if ! pkg-config --exists rsf; then
  echo "run.sh: no rsf.pc under $prefix/lib/pkgconfig: not an rsf installation (make install PREFIX=$prefix)" >&2
  exit 2
fi
# QDYN links the static library (one binary to copy to a cluster), with its pkg-config libraries
lib="$(pkg-config --variable=staticlib rsf) $(pkg-config --static --libs-only-l rsf | sed 's/-lrsf_capi//')"
fmod="$(pkg-config --variable=fortran_module rsf)"

# a fresh copy of the checkout, without its .git
fresh_copy() {
  rm -rf "$1"
  mkdir -p "$1"
  (cd "$qdyn" && tar --exclude=.git -cf - .) | (cd "$1" && tar -xf -)
}

# the patch, all of it: rsf's friction module in place of QDYN's, rsf's Fortran module beside
# it, one dependency line for make (the modules the new friction module uses), and the
# library on the link line (in build)
patch_copy() {
  cp "$here/friction.f90" "$1/src/friction.f90"
  cp "$fmod" "$1/src/rsf.f90"
  echo "friction.o: rsf.o" >> "$1/src/Makefile.depend"
}

build() { # dir, extra libs
  local log="$1/build.log"
  if ! make -C "$1/src" -j2 F90="$fc" LIBS="$2" > "$log" 2>&1; then
    echo "build failed: see $log" >&2
    tail -20 "$log" >&2
    return 1
  fi
}

status=0
declare -A unit_line suite_line suite_time
verdict=""
run_tests() { # name, dir, [results of the other build to compare with]
  local name="$1" dir="$2" other="${3:-}" t0 t1 out
  echo "== $name: QDYN's unit tests (qdyn test)"
  out="$(cd "$dir/src" && ./qdyn test 2>&1 | sed 's/\x1b\[[0-9;]*m//g')"
  echo "$out" | grep -E "passed|failed|FAILED" | sed 's/^/   /'
  unit_line[$name]="$(echo "$out" | grep -E "^ *(Kernel tests|Rate-and-state friction):" | tr -s ' ' | tr '\n' ';')"
  if echo "$out" | grep -qiE "failed"; then status=1; fi
  if ! echo "$out" | grep -q "Rate-and-state friction: 4 / 4 passed"; then status=1; fi
  if [ "$suite" = 1 ]; then
    echo "== $name: QDYN's regression suite (test/test_suite.py through suite.py; several minutes)"
    t0=$(date +%s.%N)
    local code=0
    "$py" "$here/suite.py" "$dir/test" "$work/suite_$name.json" ${other:+--against "$other"} > "$dir/suite.log" 2>&1 || code=$?
    suite_line[$name]="$(grep '^cases: ' "$dir/suite.log" | tail -1 | sed 's/^cases: //')"
    [ -n "${suite_line[$name]}" ] || suite_line[$name]="did not finish (exit $code; log: $dir/suite.log)"
    # alone, the suite's own exit status is the verdict; with --compare, the comparison with
    # QDYN's own build is (compare_suites.py below), since QDYN fails some of its own cases here
    if [ "$code" != 0 ] && [ "$compare" = 0 ]; then status=1; fi
    t1=$(date +%s.%N)
    suite_time[$name]="$(awk "BEGIN{printf \"%.1f\", $t1 - $t0}")"
    sed 's/\x1b\[[0-9;]*m//g' "$dir/suite.log" | sed -n '/Integration test results/,/Finished in/p' | sed 's/^/   /'
    sed -n '/^per case:/,$p' "$dir/suite.log" | sed 's/^/   /'
    echo "   suite: ${suite_line[$name]}, in ${suite_time[$name]} s (log: $dir/suite.log)"
  fi
}

if [ "$compare" = 1 ]; then
  echo "== QDYN on its own friction: $work/own"
  fresh_copy "$work/own"
  build "$work/own" ""
  run_tests own "$work/own"
fi
echo "== QDYN on rsf's friction: $work/rsf"
fresh_copy "$work/rsf"
patch_copy "$work/rsf"
build "$work/rsf" "$lib"
if [ "$compare" = 1 ] && [ -f "$work/suite_own.json" ]; then
  run_tests rsf "$work/rsf" "$work/suite_own.json"
else
  run_tests rsf "$work/rsf"
fi

if [ "$compare" = 1 ] && [ "$suite" = 1 ] && [ -f "$work/suite_own.json" ] && [ -f "$work/suite_rsf.json" ]; then
  echo "== QDYN's regression cases: rsf's friction against QDYN's own, same go"
  "$py" "$here/compare_suites.py" "$work/suite_own.json" "$work/suite_rsf.json" "$work/rsf/suite.log" | tee "$work/suite_table.md" || status=1
  verdict="$(tail -1 "$work/suite_table.md")"
fi

if [ -n "$bp1" ]; then
  cells="${bp1%,*}"; years="${bp1#*,}"
  for name in rsf own; do
    [ -d "$work/$name/src" ] || continue
    echo "== BP1-QD by QDYN on $name friction: $cells cells, $years yr"
    "$py" "$here/bp1.py" "$work/$name/src" --cells "$cells" --years "$years" --out "$work/bp1_$name" || status=1
  done
  echo "== BP1-QD by rsf-cycle: $cells cells, $years yr"
  (cd "$root" && cargo build --release -q -p rsf-cycle --example bp1qd) || status=1
  t0=$(date +%s.%N)
  "$root/target/release/examples/bp1qd" --cells "$cells" --years "$years" --out "$work/bp1_cycle" > "$work/bp1_cycle.log" 2>&1 || status=1
  t1=$(date +%s.%N)
  echo "{\"wall_s\": $(awk "BEGIN{printf \"%.2f\", $t1 - $t0}")}" > "$work/bp1_cycle/run.json"
  "$py" "$here/compare_bp1.py" "$work" | tee "$work/bp1_table.md"
fi

echo "== summary (QDYN $commit)"
for name in rsf own; do
  [ -n "${unit_line[$name]:-}" ] || continue
  echo "$name: unit ${unit_line[$name]} suite: ${suite_line[$name]:-not run}${suite_time[$name]:+, in ${suite_time[$name]} s}"
done
[ -z "${verdict:-}" ] || echo "compared with QDYN's own build: $verdict"
if [ "$status" = 0 ]; then
  echo "run.sh: exit 0: every test asked of rsf's friction passed"
else
  echo "run.sh: exit 1: a test asked of rsf's friction failed (above)"
fi
exit $status
