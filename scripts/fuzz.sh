#!/usr/bin/env bash
# Usage: scripts/fuzz.sh [SECONDS]   (default 60 seconds per target)
#
# Builds and runs every cargo-fuzz target of fuzz/ for SECONDS each:
# the parsers (parse_*), slice_invariants, adversarial (slivers, overlapping
# and touching copies, f32 rounding, 2^k scales, coarse snap grids, corners
# welded or not, collapsed faces refused or dropped; the slices, the
# critical values, the z- and x-mirrors and the neighbouring regular
# levels), verify_result (verify's reader of result documents),
# pickled_level (the Python package's level pickles), and
# slice_oracle when the CGAL,
# GMP, MPFR and Boost headers are present. Each run starts from the seeds
# in fuzz/corpus/seeds/TARGET and grows a scratch corpus in
# fuzz/corpus/scratch/TARGET (gitignored; kept between runs). Logs go to
# fuzz/corpus/scratch/logs/TARGET.log, crashing inputs to
# fuzz/artifacts/TARGET/. Prints the executions per target and exits
# non-zero if any target crashed (or failed to build or run); a failing
# slab target prints the case as a ready regression test for
# tests/fuzz_regressions.rs.
#
# Works on stable Rust (no sanitizer). FUZZ_SANITIZER=address uses ASan
# through RUSTC_BOOTSTRAP=1 (slower). Installs cargo-fuzz when missing.
set -uo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
secs=${1:-60}
case "$secs" in
  '' | *[!0-9]*) echo "usage: $0 [SECONDS]" >&2; exit 2 ;;
esac
start=$(date +%s)

if ! cargo fuzz --version >/dev/null 2>&1; then
  echo "== cargo install cargo-fuzz --locked"
  cargo install cargo-fuzz --locked || exit 1
fi

sanitizer=${FUZZ_SANITIZER:-none}
if [ "$sanitizer" != none ]; then
  export RUSTC_BOOTSTRAP=1
fi

# slice_oracle links the C++ CGAL oracle: only when its headers are there.
have_cgal=0
if printf '#include <CGAL/version.h>\n#include <gmp.h>\n#include <mpfr.h>\n#include <boost/version.hpp>\n' |
  g++ -E -x c++ - >/dev/null 2>&1; then
  have_cgal=1
fi

parsers=(parse_stl parse_obj parse_off parse_ply parse_3mf parse_3mf_model)
# Every target in one build (one set of flags, one target dir: a second
# instrumented build of the crate costs CI about ten minutes). Comparison
# tracing is off: for the slab targets big-rational arithmetic makes it
# costly and useless (3-5x fewer executions); the parsers lose some help
# finding keywords, which their seed corpora (every format's keywords)
# make up for. Overflow checks are on.
flags=(--sanitizer "$sanitizer" --no-trace-compares --debug-assertions
  --target-dir "$root/fuzz/target/all")
slices=(slice_invariants adversarial)
# verify's reader of result documents and the Python package's level
# pickles (seeds of a few kB each).
checks=(verify_result pickled_level)
if [ "$have_cgal" = 1 ]; then
  flags+=(--features cgal-oracle)
  slices+=(slice_oracle)
else
  echo "== CGAL/GMP/MPFR/Boost headers missing: slice_oracle skipped"
fi

scratch=$root/fuzz/corpus/scratch
mkdir -p "$scratch/logs"

status=0
declare -A result
b0=$(date +%s)
echo "== cargo fuzz build ${flags[*]}"
built=1
if ! cargo fuzz build "${flags[@]}"; then
  echo "FAILED to build the fuzz targets" >&2
  status=1
  built=0
fi
echo "== build took $(($(date +%s) - b0)) s"

# run TARGET "LIBFUZZER ARGS" CARGO-FUZZ FLAGS...
run() {
  local t=$1
  local -a extra
  read -r -a extra <<<"$2"
  shift 2
  local log=$scratch/logs/$t.log
  mkdir -p "$scratch/$t" "$root/fuzz/artifacts/$t"
  echo "== fuzz $t for ${secs} s"
  local rc=0
  cargo fuzz run "$@" "$t" "$scratch/$t" "$root/fuzz/corpus/seeds/$t" -- \
    -max_total_time="$secs" -print_final_stats=1 "${extra[@]}" >"$log" 2>&1 || rc=$?
  # The executions: libFuzzer's final statistics, else its last "#N" line.
  local n
  n=$(awk '/^stat::number_of_executed_units:/ { n = $2 } END { print n }' "$log")
  if [ -z "$n" ]; then
    n=$(grep -oE '^#[0-9]+' "$log" | tail -n 1 | tr -d '#')
  fi
  if [ "$rc" -ne 0 ] || grep -qE '^==[0-9]+== ?ERROR|deadly signal|^SUMMARY: libFuzzer' "$log"; then
    result[$t]="CRASH (exit $rc) after ${n:-?} executions; log: $log"
    status=1
    echo "---- $t failed; end of $log:"
    tail -n 60 "$log"
    echo "----"
  else
    result[$t]="${n:-?} executions"
  fi
  echo "$t: ${result[$t]}"
}

if [ "$built" = 1 ]; then
  for t in "${parsers[@]}"; do
    run "$t" "" "${flags[@]}"
  done
  for t in "${slices[@]}"; do
    run "$t" "-max_len=256 -timeout=60" "${flags[@]}"
  done
  for t in "${checks[@]}"; do
    run "$t" "-max_len=8192 -timeout=60" "${flags[@]}"
  done
fi

echo "== fuzz summary (${secs} s per target, $(($(date +%s) - start)) s in all)"
for t in "${parsers[@]}" "${slices[@]}" "${checks[@]}"; do
  printf '%-18s %s\n' "$t" "${result[$t]:-not run}"
done
exit "$status"
