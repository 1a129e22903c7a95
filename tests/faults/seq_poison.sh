#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault H3: forged commands next to a live controller (inject.py): one with
# seq = INT64_MAX - 10 of the live session, one of a second controller session, one answering
# another plant. Each must be refused and counted under its own reason (seq beyond window,
# session busy, other plant) while the honest controller keeps the winches: lockstep (the
# plant steps on each honest answer, so no count depends on the machine's load), 100 Hz,
# 10 s, no period on hold, no command refused as stale beyond the states sent again. Before the
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
# --watchdog 5: the live session's takeover window (docs/realtime.md "Sessions") must outlast a
# stall of the loaded machine; with the default 0.1 s, a forged command that came after a longer
# gap met a "silent" session and was judged on its old state_seq alone (seen once in a CI
# preview's clang stage: refused as stale, not as beyond the window).
"$bin/cdpr-rt" "$src/scenarios/paper-line.yaml" --rate 100 --duration 10 --lcm-url "$url" \
    --lockstep --watchdog 5 > "$w/rt.txt" 2> "$w/rt.err" &
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
# A state sent again in lockstep (after 0.1 s without an answer) may be answered twice; the late
# answer is stale once the plant moved on. More stale than resends: honest commands lost.
stale=$(echo "$received" | sed -n 's/.*\[stale \([0-9][0-9]*\)\].*/\1/p')
resends=$(before "$w/rt.txt" lockstep "states sent again")
[ "${stale:-0}" -le "${resends:-0}" ] ||
    fail "${stale} commands refused as stale, ${resends:-0} states sent again: honest commands lost"
hold=$(before "$w/rt.txt" commands "on hold")
[ "$hold" -eq 0 ] || fail "$hold periods on hold: the forged commands took the winches"
echo "PASS: forged commands refused and counted; the honest controller kept the winches"
