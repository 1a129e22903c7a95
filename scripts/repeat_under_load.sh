#!/bin/bash
# SPDX-License-Identifier: BSD-3-Clause
# The load-independence check (not in CI; docs/realtime.md "Tests and load"): runs the real-time,
# LCM and fault tests of one build tree N times in a row while K busy loops keep the cores
# occupied, and stops at the first failing pass. The tests assert only on counts and states the
# code controls, so a pass must not depend on how busy the machine is; this script is how that is
# shown. Each pass's result and wall time go to stdout; the ctest log of a failing pass is kept.
#
# usage: scripts/repeat_under_load.sh [--tree DIR] [--passes N] [--busy K] [--tests REGEX]
#          [--exclude REGEX]
#   --tree     a configured and built tree (default build/debug)
#   --passes   passes in a row (default 20)
#   --busy     busy loops running meanwhile (default: the number of cores; 0 for none)
#   --tests    ctest label regex (default "rt|lcm|faults|net")
#   --exclude  ctest name regex to leave out (default "load_validation": the robot-file probe
#              suite, 2 minutes of file checks with no real-time part)
# Exit status: 0 when every pass passed, 1 at the first failing pass, 2 on bad usage.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
tree="$here/build/debug"
passes=20
busy=$(nproc)
labels="rt|lcm|faults|net"
exclude="load_validation"
while [ $# -gt 0 ]; do
    case "$1" in
    --tree) tree=$2; shift 2 ;;
    --passes) passes=$2; shift 2 ;;
    --busy) busy=$2; shift 2 ;;
    --tests) labels=$2; shift 2 ;;
    --exclude) exclude=$2; shift 2 ;;
    *) echo "repeat_under_load.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
case "$passes$busy" in
*[!0-9]*) echo "repeat_under_load.sh: --passes and --busy take whole numbers" >&2; exit 2 ;;
esac
if [ ! -f "$tree/CTestTestfile.cmake" ]; then
    echo "repeat_under_load.sh: $tree is not a built tree (cmake --preset debug && cmake --build --preset debug)" >&2
    exit 2
fi
pids=()
stop_busy() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
}
trap stop_busy EXIT
for _ in $(seq 1 "$busy"); do
    (while :; do :; done) &
    pids+=($!)
done
log_dir="$tree/repeat_under_load"
mkdir -p "$log_dir"
echo "repeat_under_load: $passes passes of ctest -L '$labels' -E '$exclude' in $tree," \
    "$busy busy loops on $(nproc) cores, started $(date -u +%FT%TZ)"
for i in $(seq 1 "$passes"); do
    t0=$(date +%s)
    if ctest --test-dir "$tree" -L "$labels" -E "$exclude" --output-on-failure \
        >"$log_dir/pass-$i.log" 2>&1; then
        n=$(grep -oE 'out of [0-9]+' "$log_dir/pass-$i.log" | tail -n1 | cut -d' ' -f3)
        echo "pass $i/$passes: ok, $n tests ($(($(date +%s) - t0)) s)"
        rm -f "$log_dir/pass-$i.log"
    else
        echo "pass $i/$passes: FAILED ($(($(date +%s) - t0)) s); log: $log_dir/pass-$i.log"
        grep -A20 'The following tests FAILED' "$log_dir/pass-$i.log"
        exit 1
    fi
done
echo "repeat_under_load: $passes of $passes passes in a row, finished $(date -u +%FT%TZ)"
