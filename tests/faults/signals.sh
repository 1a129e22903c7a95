#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# SIGINT, SIGTERM and SIGHUP mid-run (issue 10, M3 and L7), each to cdpr-sim (a long
# --duration), cdpr-rt (--with-tracker over memq, --tracker-out) and cdpr-tracker (idle over
# memq, waiting for its first state): each must exit 1 (CDPR_E_INTERRUPTED), write
# summary.json with "status": "interrupted" and leave only whole rows in timeseries.csv;
# cdpr-rt must print its telemetry, cdpr-tracker must not call it an LCM failure.
# Usage: signals.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
. "$(dirname "$0")/lib.sh" "$@"
scenario=$src/scenarios/paper-line.yaml

# appears FILE PATTERN SECONDS: until FILE has a line matching PATTERN (1 if it does not in
# time: a failed check, the script goes on).
appears() {
    i=0
    while ! grep -q "$2" "$1" 2>/dev/null; do
        i=$((i + 1))
        [ "$i" -le $(($3 * 10)) ] || return 1
        sleep 0.1
    done
}

# outcome NAME RC DIR [rows]: exit 1, summary interrupted, rows whole (and some when asked).
outcome() {
    [ "$2" -eq 1 ] || bad "$1: exit $2, expected 1"
    grep -qF '"status": "interrupted",' "$3/summary.json" 2>/dev/null ||
        bad "$1: summary.json missing or not interrupted"
    whole_rows "$3/timeseries.csv" || bad "$1: a torn row"
    rows=$(grep -vc '^#' "$3/timeseries.csv" || true)
    if [ "${4:-}" = rows ] && [ "$rows" -lt 3 ]; then
        bad "$1: only $rows lines before the signal"
    fi
    echo "$1: exit $2, $rows whole lines, $(grep -F '"message"' "$3/summary.json" 2>/dev/null)"
}

for sig in INT TERM HUP; do
    d=$w/sim-$sig
    "$bin/cdpr-sim" "$scenario" --duration 300 --out "$d" --no-plot --quiet 2>"$d.err" &
    pid=$!
    appears "$d/timeseries.csv" '^1,' 60 || bad "cdpr-sim: no row after 60 s"
    kill -"$sig" "$pid"
    rc=0
    wait "$pid" || rc=$?
    outcome "cdpr-sim SIG$sig" "$rc" "$d" rows

    d=$w/rt-$sig
    "$bin/cdpr-rt" "$scenario" --rate 100 --duration 300 --lcm-url memq:// --with-tracker \
        --tracker-out "$d" >"$d.out" 2>"$d.err" &
    pid=$!
    appears "$d.err" 'running' 60 || bad "cdpr-rt: not running after 60 s"
    sleep 1
    kill -"$sig" "$pid"
    rc=0
    wait "$pid" || rc=$?
    outcome "cdpr-rt SIG$sig" "$rc" "$d" rows
    grep -q "^cdpr-rt telemetry" "$d.out" || bad "cdpr-rt SIG$sig: no telemetry printed"

    d=$w/tracker-$sig
    "$bin/cdpr-tracker" "$scenario" --lcm-url memq:// --out "$d" --no-plot >"$d.out" 2>"$d.err" &
    pid=$!
    appears "$d.err" 'waiting for' 60 || bad "cdpr-tracker: not waiting after 60 s"
    sleep 0.3
    kill -"$sig" "$pid"
    rc=0
    wait "$pid" || rc=$?
    outcome "cdpr-tracker SIG$sig" "$rc" "$d"
    if grep -q "lcm_handle failed" "$d.err"; then
        bad "cdpr-tracker SIG$sig: a signal reported as an LCM failure"
    fi
done

finish
echo "PASS: SIGINT, SIGTERM, SIGHUP: exit 1, summary interrupted, rows whole, telemetry"
