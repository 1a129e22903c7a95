#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Fault M1: cdpr-rt over udpm under an address-space limit (ulimit -v) from 20 to 60 MB in
# 4 MB steps (issue 26: between 26 and 34 MB liblcm's start-up crashed, SIGSEGV, inside
# lcm_subscribe, which does not check an allocation; 28 and 32 MB are in that band). Every run must either work (exit 0) or
# refuse at start-up with the reason (exit 3): never a crash. Skipped (77) where a run under a
# 200 MB limit cannot start at all (sanitizer builds reserve terabytes of shadow memory).
# Runs inside a private network namespace (udpm on loopback).
set -eu
. "$(dirname "$0")/lib.sh" "$@"
sc=$src/scenarios/paper-line.yaml
run_limited() {
    rc=0
    (ulimit -v "$1" && exec "$bin/cdpr-rt" "$sc" --rate 100 --duration 0.1 --lcm-url "$url") \
        > "$w/run-$1.txt" 2>&1 || rc=$?
}
run_limited 200000
if [ "$rc" -ne 0 ]; then
    cat "$w/run-200000.txt"
    echo "SKIPPED: cdpr-rt does not start under a 200 MB address-space limit (a sanitizer build)"
    exit 77
fi
worked=0
refused=0
kb=20000
while [ "$kb" -le 60000 ]; do
    run_limited "$kb"
    case $rc in
    0) worked=$((worked + 1)) ;;
    3)
        refused=$((refused + 1))
        # The bridge refusing liblcm's start-up, or (just above that) the periodic thread's
        # stack not fitting: either way a line saying what could not be done.
        grep -q "^cdpr-rt: .*cannot" "$w/run-$kb.txt" || bad "$kb kB: exit 3 without the reason"
        ;;
    *)
        cat "$w/run-$kb.txt"
        bad "$kb kB: exit code $rc (a crash is 139)"
        ;;
    esac
    kb=$((kb + 4000))
done
echo "under 20-60 MB: $worked runs worked, $refused refused at start-up"
[ "$refused" -gt 0 ] || bad "no limit was low enough to refuse: the sweep tested nothing"
[ "$worked" -gt 0 ] || bad "no limit was high enough to work"
finish
echo "PASS: no crash under any address-space limit"
