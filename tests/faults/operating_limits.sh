#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault L1: the operating limits are enforced, not silent (issue 26):
#  1. free-running at 5 Hz with the default watchdog: the watchdog follows the period (0.4 s),
#     so the controller's commands are applied (before: the 0.1 s default watchdog was shorter
#     than the 0.2 s period, the plant never applied a command and exited 0);
#  2. an explicit --watchdog shorter than two periods is refused, naming the option (exit 2);
#  3. a lockstep plant without a controller says so and stops after 30 s of unanswered periods
#     (--lockstep-timeout 0.5: 60 periods), exit 1 (before: one period per timeout, forever).
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
sc=$src/scenarios/paper-line.yaml

# 1. 5 Hz with a controller.
"$bin/cdpr-tracker" "$sc" --rate 5 --duration 4 --lcm-url "$url" --quiet --idle-exit 30 \
    > "$w/t.txt" 2>&1 &
t=$!
sleep 0.5
rc=0
"$bin/cdpr-rt" "$sc" --rate 5 --duration 4 --lcm-url "$url" > "$w/rt.txt" 2> "$w/rt.err" || rc=$?
wait "$t" || true
cat "$w/rt.txt" "$w/rt.err"
expect_exit 0 "$rc" "cdpr-rt at 5 Hz"
applied=$(before "$w/rt.txt" commands "periods with a new command")
[ "${applied:-0}" -ge 15 ] || bad "5 Hz: ${applied:-0} of 20 periods applied a new command"

# 2. A watchdog shorter than two periods.
rc=0
"$bin/cdpr-rt" "$sc" --rate 5 --duration 1 --watchdog 0.1 --lcm-url "$url" > "$w/wd.txt" 2>&1 ||
    rc=$?
cat "$w/wd.txt"
[ "$rc" -eq 2 ] || bad "--watchdog 0.1 at 5 Hz: exit $rc, expected 2"
grep -q "option --watchdog: 0.1 s is shorter than two control periods" "$w/wd.txt" ||
    bad "--watchdog 0.1 at 5 Hz: not refused by name"

# 3. Lockstep without a controller.
rc=0
timeout 120 "$bin/cdpr-rt" "$sc" --rate 100 --duration 10 --lockstep --lockstep-timeout 0.5 \
    --lcm-url "$url" > "$w/ls.txt" 2>&1 || rc=$?
cat "$w/ls.txt"
[ "$rc" -eq 1 ] || bad "lockstep without a controller: exit $rc, expected 1"
grep -q "lockstep: no controller answered for 60 periods in a row" "$w/ls.txt" ||
    bad "lockstep without a controller: no reason given"
finish
echo "PASS: the watchdog follows the period, a short one is refused, lockstep alone stops"
