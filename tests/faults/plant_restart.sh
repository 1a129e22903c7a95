#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault H2: the plant is killed (SIGKILL) under a running tracker and a new one started. The
# new plant is a new plant session: the tracker reports the restart on stderr, starts its
# controller again from t = 0 and answers the new plant from state 0 (docs/realtime.md,
# "Sessions"). Free-running, 100 Hz, 4 s: the new plant must be on hold only at its start
# (< 0.5 s of periods), take > 300 of its 400 periods with a new command, and the tracker must
# finish the new plant's run with exit 0. Before sessions, the tracker ignored every state seq
# up to the last one it had answered: the new plant ran on hold for as long as the first had.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
sc=$src/scenarios/paper-line.yaml
common="--rate 100 --duration 4 --lcm-url $url"

"$bin/cdpr-tracker" "$sc" $common --idle-exit 30 --out "$w/tracker" --no-plot \
    > "$w/t.txt" 2> "$w/t.err" &
t=$!
sleep 0.5
"$bin/cdpr-rt" "$sc" $common --watchdog 0.1 > "$w/rt1.txt" 2> "$w/rt1.err" &
rt1=$!
wait_for "$w/rt1.err" "running" 60
sleep 2
kill -KILL "$rt1" 2>/dev/null || fail "the first plant ended before it was killed"
wait "$rt1" 2>/dev/null || true
"$bin/cdpr-rt" "$sc" $common --watchdog 0.1 > "$w/rt2.txt" 2> "$w/rt2.err"
cat "$w/rt2.txt"
rc=0
wait "$t" || rc=$?
cat "$w/t.err"
expect_exit 0 "$rc" "the tracker across a plant restart"
grep -q "plant restarted" "$w/t.err" || fail "the tracker did not report the plant restart"
hold=$(before "$w/rt2.txt" commands "on hold")
applied=$(num "$w/rt2.txt" commands)
[ "$hold" -lt 50 ] || fail "the new plant was on hold for $hold periods (< 50 expected)"
[ "$applied" -gt 300 ] || fail "the new plant took only $applied periods with a new command"
echo "PASS: the tracker followed the restarted plant ($applied new commands, $hold on hold)"
