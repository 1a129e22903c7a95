#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Flood (a probe that held before sessions; kept as a regression test): for 3 s a second
# publisher floods the command channel as fast as it can with a replayed copy of the live
# controller's command and 12-byte garbage (inject.py --flood). The plant must count them all
# as refused (replayed/stale or wrong type), keep publishing, and the honest controller must
# keep the winches: free-running, 100 Hz, 5 s, exit 0, on hold < 0.5 s of periods, at least
# 10 000 refused, no ring drop.
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
python_or_skip
tracker_then_plant "$src/scenarios/paper-line.yaml" "--rate 100 --duration 5 --lcm-url $url"
sleep 0.5
"$py" "$(dirname "$0")/inject.py" "$url" --flood 3 > "$w/inject.txt" 2>&1 ||
    { cat "$w/inject.txt"; fail "inject.py"; }
rc=0
wait "$rt" || rc=$?
wait "$t" || true
cat "$w/rt.txt" "$w/inject.txt"
expect_exit 0 "$rc" "cdpr-rt under a flood"
ignored=$(before "$w/rt.txt" received ignored)
[ "$ignored" -ge 10000 ] || fail "only $ignored messages refused: the flood did not arrive"
hold=$(before "$w/rt.txt" commands "on hold")
[ "$hold" -lt 50 ] || fail "$hold periods on hold: the flood took the winches"
grep -q "ring dropped 0," "$w/rt.txt" || fail "the plant dropped messages under the flood"
echo "PASS: $ignored flooded messages refused; the honest controller kept the winches"
