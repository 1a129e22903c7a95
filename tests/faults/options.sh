#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Options and the outputs they set (issue 10, L3 and L10):
#  1. a --duration that is not a whole number of control periods is refused (exit 2) by
#     cdpr-sim, cdpr-rt and cdpr-tracker with the message the same value gets in the scenario
#     file -- never rounded;
#  2. run.output_rate_hz is honoured by the tracker's recorder (cdpr-rt --with-tracker
#     --tracker-out): rows at the output instants and the last state, as cdpr-sim writes them
#     -- lockstep and free-running, at the file's rate and at --rate 500.
# Usage: options.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
. "$(dirname "$0")/lib.sh" "$@"

# 1. --duration 0.015 at 100 Hz (1.5 periods), and the same value in the file.
line=$src/scenarios/paper-line.yaml
sed 's/^  duration_s: 15.0 .*/  duration_s: 0.015/' "$line" >"$w/frac.yaml"
grep -q '^  duration_s: 0.015$' "$w/frac.yaml" || { echo "FAIL: could not edit the scenario"; exit 1; }
why="run.duration_s: 0.015 s is not a whole number of control periods (0.01 s)"
for app in cdpr-sim cdpr-rt cdpr-tracker; do
    extra=
    [ "$app" = cdpr-sim ] && extra="--out $w/never"
    [ "$app" != cdpr-sim ] && extra="--lcm-url memq://"
    for how in option file; do
        rc=0
        if [ "$how" = option ]; then
            # shellcheck disable=SC2086
            "$bin/$app" "$line" --duration 0.015 $extra >"$w/out" 2>"$w/err" || rc=$?
        else
            # shellcheck disable=SC2086
            "$bin/$app" "$w/frac.yaml" $extra >"$w/out" 2>"$w/err" || rc=$?
        fi
        [ "$rc" -eq 2 ] || bad "$app: fractional duration ($how): exit $rc, expected 2"
        grep -qF "$why" "$w/err" || bad "$app: fractional duration ($how): $(cat "$w/err")"
    done
done
[ ! -e "$w/never" ] || bad "cdpr-sim wrote outputs for a refused duration"
echo "fractional --duration: refused by every app as in the file ($why)"

# 2. deploy-retrieve: 100 Hz control, output_rate_hz 50 (a row every 2 periods). 1.01 s = 101
#    periods: rows at 0, 0.02, ..., 1.00 and the last state 1.01 = 52, as cdpr-sim writes.
dr=$src/scenarios/deploy-retrieve.yaml
grep -q '^  output_rate_hz: 50$' "$dr" || { echo "FAIL: $dr no longer says output_rate_hz: 50"; exit 1; }
rows() { grep -v '^#' "$1/timeseries.csv" | tail -n +2 | wc -l; }
"$bin/cdpr-sim" "$dr" --duration 1.01 --out "$w/sim" --no-plot --quiet 2>/dev/null
[ "$(rows "$w/sim")" -eq 52 ] || bad "cdpr-sim wrote $(rows "$w/sim") rows, expected 52"
"$bin/cdpr-rt" "$dr" --duration 1.01 --lockstep --lcm-url memq:// --with-tracker \
    --tracker-out "$w/lock" --quiet 2>/dev/null
[ "$(rows "$w/lock")" -eq 52 ] || bad "lockstep: the tracker wrote $(rows "$w/lock") rows, expected 52"
# Same instants as the batch run (the first column).
grep -v '^#' "$w/sim/timeseries.csv" | cut -d, -f1 >"$w/t-sim"
grep -v '^#' "$w/lock/timeseries.csv" | cut -d, -f1 >"$w/t-lock"
cmp -s "$w/t-sim" "$w/t-lock" || bad "lockstep: the tracker's row times differ from cdpr-sim's"
# Free-running at 500 Hz for 1.01 s: 505 periods, a row every 10: 0, 0.02, ..., 1.00 and 1.01.
"$bin/cdpr-rt" "$dr" --rate 500 --duration 1.01 --lcm-url memq:// --with-tracker \
    --tracker-out "$w/free" --quiet 2>/dev/null
n=$(rows "$w/free")
[ "$n" -ge 51 ] && [ "$n" -le 52 ] || bad "free-running at 500 Hz: $n rows, expected 51..52 (50 Hz)"
echo "output_rate_hz 50: cdpr-sim $(rows "$w/sim"), tracker lockstep $(rows "$w/lock"), free-running at 500 Hz $n rows"

finish
echo "PASS: fractional durations refused as in the file; the tracker's rows at run.output_rate_hz"
