#!/usr/bin/env bash
# The whole test suite: unit, integration, property and doc tests.
# Ends with one plain line "N passed, N failed" summed over every test binary.
set -uo pipefail
cd "$(dirname "$0")/.."
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
# The CGAL oracle (feature cgal-oracle) needs Debian's CGAL, GMP, MPFR and
# Boost headers; install them when missing (set WMSLICE_NO_ORACLE=1 to skip).
features=()
if [ "${WMSLICE_NO_ORACLE:-0}" != 1 ]; then
  pkgs=(libcgal-dev libgmp-dev libmpfr-dev libboost-dev g++)
  if ! dpkg -s "${pkgs[@]}" >/dev/null 2>&1; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${pkgs[@]}" >/dev/null
  fi
  features=(--features cgal-oracle)
fi
# The browser test drives Debian's headless Chromium (set WMSLICE_NO_BROWSER=1
# to skip installing it; the test then skips unless CI is set).
if [ "${WMSLICE_NO_BROWSER:-0}" != 1 ] && ! command -v chromium >/dev/null 2>&1; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
cargo test --all-targets --no-fail-fast "${features[@]}" "$@" 2>&1 | tee -a "$log" || status=1
cargo test --doc --no-fail-fast "$@" 2>&1 | tee -a "$log" || status=1
# The Python package (set WMSLICE_NO_PYTHON=1 to skip): its pytest summary
# ("N failed, N passed, N skipped in Ts") is added to the counts below.
pylog=$(mktemp)
trap 'rm -f "$log" "$pylog"' EXIT
if [ "${WMSLICE_NO_PYTHON:-0}" != 1 ]; then
  bash scripts/python-test.sh 2>&1 | tee "$pylog" || status=1
fi
passed=$(awk '/^test result:/ { for (i = 1; i < NF; i++) if ($(i+1) ~ /^passed/) s += $i } END { print s + 0 }' "$log")
failed=$(awk '/^test result:/ { for (i = 1; i < NF; i++) if ($(i+1) ~ /^failed/) s += $i } END { print s + 0 }' "$log")
py_summary='/^(=+ )?[0-9]+ (passed|failed|errors?|skipped).* in [0-9.]+s/'
py_passed=$(awk "$py_summary"' { for (i = 1; i < NF; i++) if ($(i+1) ~ /^passed/) s += $i } END { print s + 0 }' "$pylog")
py_failed=$(awk "$py_summary"' { for (i = 1; i < NF; i++) if ($(i+1) ~ /^(failed|errors?)/) s += $i } END { print s + 0 }' "$pylog")
passed=$((passed + py_passed))
failed=$((failed + py_failed))
echo "${passed:-0} passed, ${failed:-0} failed"
[ "${failed:-0}" -eq 0 ] && [ "$status" -eq 0 ]
