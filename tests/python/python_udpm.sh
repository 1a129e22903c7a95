#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# examples/python/{subscriber,controller}.py against cdpr-rt over udpm (inside the private
# network namespace of run_in_netns.sh; ttl=0):
#  1. lockstep: the Python controller answers every state, so the plant steps all 100 periods
#     on its commands (0 lockstep timeouts, none on hold) and accepts them (>= 100 accepted;
#     the answer to the final state 100 may come after the plant's end; ignored only the second
#     answers to states sent again, which a loaded machine causes), while the
#     subscriber decodes all 101 states and tension messages and prints each shown state with
#     its own period's tensions, equal (to the 0.1 N printed) to what lcm-logger recorded on the
#     wire for that seq;
#  2. free-running: the plant does not wait; it must still accept the controller's commands
#     (some accepted, none ignored: how many periods a free-running controller answers in time
#     depends on the machine's load, so no share is asserted; lockstep above counts them all);
#  3. with EIGHT (a scenario of an eight-cable robot, given for builds that hold eight cables):
#     lockstep again, the same controller sizing its commands by the plant's cable count: all
#     100 periods stepped on its commands, every one accepted.
# PYTHONPATH (tests/python/CMakeLists.txt) holds LCM's Python module and the generated types.
# Usage: python_udpm.sh BUILD_DIR SOURCE_DIR WORK_DIR PYTHON [EIGHT]
set -eu
bin=$1/apps
src=$2
w=$3
py=$4
eight=${5:-}
scenario=$src/scenarios/paper-line.yaml
url='udpm://239.255.76.67:7667?ttl=0'
rm -rf "$w"
mkdir -p "$w"
[ -x "$py" ] || { echo "SKIPPED: $py not found"; exit 77; }
if ! "$py" -c 'import lcm, cdpr.cabin_state_t' 2> "$w/import.txt"; then
    cat "$w/import.txt"
    echo "SKIPPED: LCM's Python module is not importable (PYTHONPATH=${PYTHONPATH:-}); scripts/setup.sh builds it"
    exit 77
fi
fail() {
    echo "FAIL: $*"
    exit 1
}
# accepted and ignored: the plant's "received N accepted, M ignored" line of the report $1;
# replayed: how many of the ignored were second copies ("[replayed K]"), resent: the lockstep
# line's "S states sent again".
counts() {
    accepted=$(sed -n 's/^ *received *\([0-9]*\) accepted, \([0-9]*\) ignored.*/\1/p' "$1")
    ignored=$(sed -n 's/^ *received *\([0-9]*\) accepted, \([0-9]*\) ignored.*/\2/p' "$1")
    replayed=$(sed -n 's/^ *received .*replayed \([0-9]*\).*/\1/p' "$1")
    replayed=${replayed:-0}
    resent=$(sed -n 's/^ *lockstep .* \([0-9]*\) states sent again.*/\1/p' "$1")
    resent=${resent:-0}
}
# lockstep_counts WHAT: every period's command accepted; the only commands ignored are second
# answers to a state the plant sent again (a controller slower than 0.1 s on a loaded machine
# gets state k twice and answers both; the plant ignores the second as replayed:
# docs/realtime.md), so ignored = replayed <= resent.
lockstep_counts() {
    [ -n "$accepted" ] && [ "$accepted" -ge 100 ] && [ "$ignored" -eq "$replayed" ] &&
        [ "$replayed" -le "$resent" ] ||
        fail "$1: ${accepted:-?} commands accepted, ${ignored:-?} ignored ($replayed replayed, $resent states sent again)"
}

# 1. Lockstep.
lcm-logger --lcm-url="$url" -c '^CDPR_CABLE_TENSIONS$' -f "$w/tensions.lcmlog" \
    > "$w/logger.txt" 2>&1 &
logger=$!
"$py" "$src/examples/python/subscriber.py" --lcm-url "$url" --count 101 --timeout 20 \
    --every 20 > "$w/sub.txt" 2>&1 &
sub=$!
"$py" "$src/examples/python/controller.py" --lcm-url "$url" --count 101 --timeout 20 \
    > "$w/ctl.txt" 2>&1 &
ctl=$!
sleep 1
"$bin/cdpr-rt" "$scenario" --rate 100 --duration 1 --lockstep --max-trials 2000 \
    --lcm-url "$url" > "$w/rt.txt"
status=0
wait "$ctl" || status=$?
wait "$sub" || status=$?
sleep 1 # lcm-logger flushes every 100 ms; and reads what its socket still holds
kill -INT "$logger" 2> /dev/null || true
wait "$logger" || true
cat "$w/rt.txt" "$w/ctl.txt" "$w/sub.txt"
[ "$status" -eq 0 ] || fail "a Python example exited with an error"
grep -q "0 timeouts" "$w/rt.txt" || fail "lockstep timeouts"
grep -q "100 periods with a new command, 0 on hold" "$w/rt.txt" ||
    fail "the plant did not step every period on a Python command"
counts "$w/rt.txt"
lockstep_counts lockstep
grep -q "answered 101 states (last state seq 100)" "$w/ctl.txt" || fail "controller count"
grep -q "101 states and 101 tension messages decoded" "$w/sub.txt" || fail "subscriber count"
# Every shown state carries its period's tensions, as the plant sent them (lcm-logger's record).
"$py" - "$w/sub.txt" "$w/tensions.lcmlog" << 'EOF' || fail "subscriber tensions"
import re
import sys

import lcm
from cdpr import cable_tensions_t

wire = {}
for ev in lcm.EventLog(sys.argv[2], "r"):
    m = cable_tensions_t.decode(ev.data)
    wire[m.seq] = ["%7.1f" % x for x in m.tension_cabin_N[:m.n_cables]]
shown = 0
for line in open(sys.argv[1]):
    g = re.match(r"t=.* seq= *(\d+) .*(no tensions|T=\[(.*)\] N)$", line.rstrip())
    if not g:
        continue
    seq = int(g.group(1))
    if g.group(3) is None:
        sys.exit("seq %d shown without tensions" % seq)
    printed = [x for x in g.group(3).split(" ") if x]
    want = [x.strip() for x in wire.get(seq, [])]
    if printed != want:
        sys.exit("seq %d: printed %s, on the wire %s" % (seq, printed, want))
    shown += 1
if shown < 5:
    sys.exit("only %d states shown with tensions" % shown)
print("subscriber tensions: %d shown states match the wire (%d logged)" % (shown, len(wire)))
EOF
echo "PASS: lockstep, $accepted Python commands accepted, 101 states decoded"

# 2. Free-running.
"$py" "$src/examples/python/controller.py" --lcm-url "$url" --timeout 5 > "$w/ctl2.txt" 2>&1 &
ctl=$!
sleep 1
"$bin/cdpr-rt" "$scenario" --rate 100 --duration 1 --max-trials 2000 --lcm-url "$url" \
    > "$w/rt2.txt"
wait "$ctl" || fail "controller.py exited with an error (free-running)"
cat "$w/rt2.txt" "$w/ctl2.txt"
counts "$w/rt2.txt"
[ -n "$accepted" ] && [ "$accepted" -ge 1 ] || fail "free-running: ${accepted:-?} commands accepted"
[ "$ignored" -eq 0 ] || fail "free-running: $ignored commands ignored"
echo "PASS: free-running, $accepted Python commands accepted, none ignored"

# 3. Eight cables, lockstep.
[ -n "$eight" ] || exit 0
"$py" "$src/examples/python/controller.py" --lcm-url "$url" --count 101 --timeout 20 \
    > "$w/ctl3.txt" 2>&1 &
ctl=$!
sleep 1
"$bin/cdpr-rt" "$eight" --rate 100 --duration 1 --lockstep --max-trials 2000 \
    --lcm-url "$url" > "$w/rt3.txt"
wait "$ctl" || fail "controller.py exited with an error (eight cables)"
cat "$w/rt3.txt" "$w/ctl3.txt"
grep -q "0 timeouts" "$w/rt3.txt" || fail "eight cables: lockstep timeouts"
grep -q "100 periods with a new command, 0 on hold" "$w/rt3.txt" ||
    fail "eight cables: the plant did not step every period on a Python command"
counts "$w/rt3.txt"
lockstep_counts "eight cables"
grep -q "answered 101 states (last state seq 100) of a 8-cable plant" "$w/ctl3.txt" ||
    fail "eight cables: controller count"
echo "PASS: eight cables in lockstep, $accepted Python commands of eight values accepted"
