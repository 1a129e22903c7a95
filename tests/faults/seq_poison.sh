#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault H3: forged commands next to a live controller (inject.py): one with
# seq = INT64_MAX - 10 of the live session, one of a second controller session, one answering
# another plant. Each must be refused and counted under its own reason (seq beyond window,
# session busy, other plant) while the honest controller keeps the winches: lockstep (the
# plant steps on each honest answer, so no count depends on the machine's load), 100 Hz,
# 10 s, no period on hold, no command refused as stale. Before the
# sequence window, the poisoned seq was adopted and every honest command after it was stale:
# the plant held until the end.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
python_or_skip
"$bin/cdpr-tracker" "$src/scenarios/paper-line.yaml" --rate 100 --duration 10 --lcm-url "$url" \
    --quiet --idle-exit 30 > "$w/t.txt" 2>&1 &
t=$!
sleep 0.5
"$bin/cdpr-rt" "$src/scenarios/paper-line.yaml" --rate 100 --duration 10 --lcm-url "$url" \
    --lockstep > "$w/rt.txt" 2> "$w/rt.err" &
rt=$!
"$py" "$(dirname "$0")/inject.py" "$url" > "$w/inject.txt" 2>&1 || { cat "$w/inject.txt"; fail "inject.py"; }
rc=0
wait "$rt" || rc=$?
wait "$t" || true
cat "$w/rt.txt" "$w/inject.txt"
expect_exit 0 "$rc" "cdpr-rt under forged commands"
received=$(grep "^  received" "$w/rt.txt")
for r in "seq beyond window 1" "session busy 1" "other plant 1"; do
    echo "$received" | grep -q "\[$r\]" || fail "not refused and counted once: $r"
done
echo "$received" | grep -q "stale" && fail "honest commands were refused as stale"
hold=$(before "$w/rt.txt" commands "on hold")
[ "$hold" -eq 0 ] || fail "$hold periods on hold: the forged commands took the winches"
echo "PASS: forged commands refused and counted; the honest controller kept the winches"
