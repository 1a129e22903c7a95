#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Faults L1 and L2 of cdpr-rt's run options (in-process tracker over memq://, no network):
#  L1 --duration is plant time: a normal run reaches exactly that plant time; a plant that
#     cannot advance (--max-trials 1 --max-attempts 1: every period refused) stops after 1 s of
#     failed periods with exit 1 and says why (before: 1 998 of 2 000 periods refused, plant
#     time 2 ms, exit 0);
#  L2 a control rate below the default message rates (--rate 5) runs (before: refused for a
#     cable-shape rate the user never set); a rate the machine cannot hold (--rate 1000000) is
#     reported on stderr within the first second and in the telemetry (before: no word).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
sc=$src/scenarios/paper-line.yaml
run() {
    rc=0
    "$bin/cdpr-rt" "$sc" --lcm-url memq:// --with-tracker "$@" > "$w/out.txt" 2> "$w/err.txt" ||
        rc=$?
}

run --rate 100 --duration 2
expect_exit 0 "$rc" "a normal run"
grep -q "plant time 2.000 s" "$w/out.txt" || fail "--duration 2 did not give 2 s of plant time"

run --rate 100 --duration 2 --max-trials 1 --max-attempts 1
cat "$w/err.txt"
expect_exit 1 "$rc" "a plant that cannot advance"
grep -q "could not advance: 100 periods in a row failed" "$w/err.txt" ||
    fail "no reason given for the stalled plant"

run --rate 5 --duration 2
cat "$w/err.txt"
expect_exit 0 "$rc" "--rate 5"
grep -q "plant time 2.000 s" "$w/out.txt" || fail "--rate 5 did not run 2 s"

run --rate 1000000 --duration 0.05
expect_exit 0 "$rc" "--rate 1000000"
grep -q "does not hold 1000000 Hz" "$w/err.txt" || fail "the overload was not reported on stderr"
grep -q "^  OVERLOAD" "$w/out.txt" || fail "the overload is not in the telemetry"
echo "PASS: --duration is plant time, a stalled plant stops with a reason, --rate 5 runs, an overload is reported"
