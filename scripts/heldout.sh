#!/usr/bin/env bash
# Usage: scripts/heldout.sh [--snap Q] [--weld] [--drop-collapsed] [--max N] MESH...
#
# Slices meshes you did not make at their hardest levels and re-checks
# every result independently: for each mesh that `wmslice check` accepts
# (others are listed with their refusal), the exact critical heights
# (`wmslice critical`: flats, ridges, extrema, saddles; at most N of them,
# default 400, evenly picked) and the midpoint between each two
# consecutive ones are sliced with `--exact` JSON, and `wmslice verify`
# re-derives S_O, L- and L+ and the SPEC 7 invariants from the mesh alone.
# Prints one line per mesh; exits non-zero when a mesh the checker
# accepted fails to slice or to verify (the worst bug: an internal error
# or a wrong answer on an accepted mesh). Never commit the meshes: fetch
# them (e.g. trimesh's models/, manifold's test/models/). WMSLICE picks
# the binary (default: this tree's, built when stale).
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
snap=(); drop=(); max=400
while [ $# -gt 0 ]; do
    case "$1" in
        --snap) snap=(--snap "$2"); shift ;;
        --drop-collapsed) drop+=(--drop-collapsed) ;;
        --weld) drop+=(--weld) ;;
        --max) max="$2"; shift ;;
        -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
        *) break ;;
    esac
    shift
done
# The binary of this tree (built when stale), or WMSLICE when set.
if [ -n "${WMSLICE:-}" ]; then
    wm="$WMSLICE"
else
    (cd "$root" && cargo build --release --quiet --bin wmslice) || exit 2
    wm="${CARGO_TARGET_DIR:-$root/target}/release/wmslice"
fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
failed=0
for m in "$@"; do
    n=$(basename "$m")
    if ! "$wm" check "$m" "${snap[@]}" "${drop[@]}" > "$tmp/check" 2>&1; then
        echo "refused  $n: $(grep -m1 '^error' "$tmp/check" | cut -c1-150)"
        continue
    fi
    if ! "$wm" critical "$m" "${snap[@]}" "${drop[@]}" --format json -o "$tmp/critical.json" 2> "$tmp/err"; then
        echo "FAILED   $n: critical: $(head -c 300 "$tmp/err")"; failed=1; continue
    fi
    python3 "$root/scripts/critical_levels.py" "$tmp/critical.json" "$max" > "$tmp/levels"
    levels=$(wc -l < "$tmp/levels")
    if [ "$levels" = 0 ]; then echo "skipped  $n: no critical height"; continue; fi
    if ! "$wm" slice "$m" "${snap[@]}" "${drop[@]}" --levels-file "$tmp/levels" --exact --format json \
            --quiet -o "$tmp/result.json" 2> "$tmp/err"; then
        echo "FAILED   $n: slice: $(head -c 300 "$tmp/err")"; failed=1; continue
    fi
    if "$wm" verify "$m" "$tmp/result.json" "${snap[@]}" > "$tmp/verify" 2>&1; then
        echo "verified $n: $levels levels ($(tail -1 "$tmp/verify" | sed 's/.*verified: //' | cut -c1-120))"
    else
        echo "FAILED   $n: verify: $(tail -3 "$tmp/verify" | head -c 400)"; failed=1
    fi
done
exit $failed
