#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault M4: two plants on one channel prefix with one tracker. The policy (docs/realtime.md,
# "One plant per channel"): each plant warns on stderr as soon as it sees the other's states,
# counts them, runs to its end and exits 5; the tracker follows one plant, ignores and counts
# the other's states, warns, and exits 5. Before sessions, neither noticed: the tracker mixed
# both plants' states and everyone exited 0.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
sc=$src/scenarios/paper-line.yaml
common="--rate 100 --duration 3 --lcm-url $url"

"$bin/cdpr-tracker" "$sc" $common --quiet --idle-exit 30 > "$w/t.txt" 2> "$w/t.err" &
t=$!
sleep 0.5
"$bin/cdpr-rt" "$sc" $common > "$w/a.txt" 2> "$w/a.err" &
a=$!
"$bin/cdpr-rt" "$sc" $common > "$w/b.txt" 2> "$w/b.err" &
b=$!
ra=0
rb=0
rt=0
wait "$a" || ra=$?
wait "$b" || rb=$?
wait "$t" || rt=$?
cat "$w/a.txt" "$w/a.err" "$w/t.err"
expect_exit 5 "$ra" "plant A"
expect_exit 5 "$rb" "plant B"
expect_exit 5 "$rt" "the tracker"
for f in a b; do
    grep -q "another plant" "$w/$f.err" || fail "plant $f did not warn"
    grep -q "^  OTHER PLANT" "$w/$f.txt" || fail "plant $f's telemetry does not count the other"
done
grep -q "another plant" "$w/t.err" || fail "the tracker did not warn"
echo "PASS: two plants on one channel: both plants and the tracker said so (exit 5)"
