#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault H4: forged plant states next to a live plant (inject_state.py): pairs of the live
# session with seq = k + 2^40, with a winch-end tension of 1e300 N, with the time of the end of
# an 8 s run; three rounds. The controller must refuse them and keep controlling:
#  1. cdpr-tracker on paper-line-hold (tension feedback, the filter a forged tension stuck in):
#     lockstep, 100 Hz, 4 s; both exit 0, the summary says ok, every winch's payout stays below
#     1 m/s (before: the 1e300 N tension stuck in the filter, every winch paid out at 4 m/s for
#     the rest of the run, the cabin fell, and the tracker said "ok"), the whole run answered
#     (before: the 2^40 seq made it ignore every real state; the forged end time stopped it at
#     2.2 s of 8 s).
#  2. examples/python/controller.py (--period 0.01), the same injection: exit 0, every forged
#     pair refused and counted (3 outside the window, 3 with a bad time, 3 implausible), the
#     plant stepped every period on its commands.
# Lockstep: the plant steps only on an answer, so nothing here depends on the machine's speed.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
python_or_skip
sc=$src/scenarios/paper-line-hold.yaml
common="--rate 100 --duration 4 --lcm-url $url"

# 1. cdpr-tracker.
"$bin/cdpr-tracker" "$sc" $common --out "$w/t" --no-plot --idle-exit 60 > "$w/t.txt" 2>&1 &
t=$!
wait_for "$w/t.txt" "waiting for" 120
"$py" "$(dirname "$0")/inject_state.py" "$url" > "$w/inject.txt" 2>&1 &
inj=$!
timeout 120 "$bin/cdpr-rt" "$sc" $common --lockstep --max-trials 2000 > "$w/rt.txt" 2> "$w/rt.err" &
rt=$!
rc=0
wait "$rt" || rc=$?
trc=0
wait "$t" || trc=$?
irc=0
wait "$inj" || irc=$?
cat "$w/rt.txt" "$w/t.txt" "$w/inject.txt"
expect_exit 0 "$irc" "inject_state.py"
expect_exit 0 "$rc" "cdpr-rt under forged states"
expect_exit 0 "$trc" "cdpr-tracker under forged states"
grep -qF '"status": "ok",' "$w/t/summary.json" || fail "the tracker's summary does not say ok"
"$py" - "$w/t/summary.json" <<'PY' || fail "a winch ran off"
import json, sys
s = json.load(open(sys.argv[1]))
u = s["max_payout_m_per_s"]
print("max payout %.3f m/s, sim time %.2f s" % (u, s["sim_time_s"]))
sys.exit(0 if u < 1.0 and s["sim_time_s"] > 3.99 else 1)
PY
grep -q "refused states:" "$w/t.txt" || fail "the tracker did not report refused states"
echo "PASS: cdpr-tracker refused the forged states and kept the cabin"

# 2. The Python example controller.
"$py" "$src/examples/python/controller.py" --lcm-url "$url" --count 401 --timeout 30 \
    --period 0.01 > "$w/ctl.txt" 2>&1 &
ctl=$!
sleep 1
"$py" "$(dirname "$0")/inject_state.py" "$url" > "$w/inject2.txt" 2>&1 &
inj=$!
timeout 120 "$bin/cdpr-rt" "$sc" $common --lockstep --max-trials 2000 > "$w/rt2.txt" 2> "$w/rt2.err" &
rt=$!
rc=0
wait "$rt" || rc=$?
crc=0
wait "$ctl" || crc=$?
irc=0
wait "$inj" || irc=$?
cat "$w/rt2.txt" "$w/ctl.txt" "$w/inject2.txt"
expect_exit 0 "$irc" "inject_state.py (Python)"
expect_exit 0 "$rc" "cdpr-rt under forged states (Python)"
expect_exit 0 "$crc" "controller.py under forged states"
grep -q "refused states: 3 outside the sequence window, 3 with a bad time, 3 implausible" \
    "$w/ctl.txt" || fail "controller.py did not refuse and count every forged pair"
grep -q "400 periods with a new command, 0 on hold" "$w/rt2.txt" ||
    fail "the plant did not step every period on the Python controller's commands"
echo "PASS: controller.py refused and counted every forged state"
