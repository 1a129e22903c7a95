#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Flood (a probe that held before sessions; kept as a regression test): for 3 s a second
# publisher floods the command channel as fast as it can with a replayed copy of the live
# controller's command and 12-byte garbage (inject.py --flood). The plant must count them all
# as refused (replayed/stale or wrong type), keep publishing, and the honest controller must
# keep the winches: lockstep (each period steps on the honest answer: nothing here depends on
# the machine's load; how many flooded messages arrive does, so only "some" is asserted),
# 100 Hz, 15 s, exit 0, no period on hold, no ring drop.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
python_or_skip
"$bin/cdpr-tracker" "$src/scenarios/paper-line.yaml" --rate 100 --duration 15 --lcm-url "$url" \
    --quiet --idle-exit 30 > "$w/t.txt" 2>&1 &
t=$!
sleep 0.5
"$bin/cdpr-rt" "$src/scenarios/paper-line.yaml" --rate 100 --duration 15 --lcm-url "$url" \
    --lockstep > "$w/rt.txt" 2> "$w/rt.err" &
rt=$!
"$py" "$(dirname "$0")/inject.py" "$url" --flood 3 > "$w/inject.txt" 2>&1 ||
    { cat "$w/inject.txt"; fail "inject.py"; }
rc=0
wait "$rt" || rc=$?
wait "$t" || true
cat "$w/rt.txt" "$w/inject.txt"
expect_exit 0 "$rc" "cdpr-rt under a flood"
ignored=$(before "$w/rt.txt" received ignored)
[ "$ignored" -ge 1 ] || fail "no message refused: the flood did not arrive"
hold=$(before "$w/rt.txt" commands "on hold")
[ "$hold" -eq 0 ] || fail "$hold periods on hold: the flood took the winches"
grep -q "ring dropped 0," "$w/rt.txt" || fail "the plant dropped messages under the flood"
echo "PASS: $ignored flooded messages refused; the honest controller kept the winches"
