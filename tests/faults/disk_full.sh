#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Outputs on a full device (issue 10, M2): cdpr-sim --out and cdpr-rt --with-tracker
# --tracker-out into a 48 KiB tmpfs (a private mount namespace: unshare -m) must exit 3, name
# the file with strerror ("No space left on device") and leave only whole rows in
# timeseries.csv. Then the same with a file-size limit (ulimit -f, SIGXFSZ ignored) that
# stops the CSV while summary.json still fits: that summary must say "io_error".
# Usage: disk_full.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
. "$(dirname "$0")/lib.sh" "$@"
scenario=$src/scenarios/paper-line.yaml

if [ "${CDPR_IN_MOUNT_NS:-}" != 1 ]; then
    if ! unshare -m true 2>/dev/null; then
        echo "SKIPPED: unshare -m not permitted here"
        exit 77
    fi
    CDPR_IN_MOUNT_NS=1 exec unshare -m "$0" "$@"
fi
mkdir -p "$w/full"
if ! mount -t tmpfs -o size=48k tmpfs "$w/full" 2>"$w/mount.err"; then
    echo "SKIPPED: cannot mount a tmpfs: $(cat "$w/mount.err")"
    exit 77
fi


# expect_full NAME RC ERRFILE CSV: exit 3, the file named with strerror, rows whole.
expect_full() {
    [ "$2" -eq 3 ] || bad "$1: exit $2, expected 3"
    grep -qF "$4: write failed: No space left on device" "$3" ||
        bad "$1: stderr does not name $4 with 'No space left on device': $(cat "$3")"
    whole_rows "$4" || bad "$1: a torn row in $4"
    rows=$(grep -vc '^#' "$4" || true)
    [ "$rows" -gt 2 ] || bad "$1: only $rows lines in $4 (the device should hold some)"
    echo "$1: exit $2, $rows whole lines, $(grep -F 'write failed' "$3" | head -1)"
}

rc=0
"$bin/cdpr-sim" "$scenario" --duration 3 --out "$w/full/sim" --no-plot --quiet \
    2>"$w/sim.err" || rc=$?
expect_full cdpr-sim "$rc" "$w/sim.err" "$w/full/sim/timeseries.csv"
rm -rf "$w/full/sim"

rc=0
"$bin/cdpr-rt" "$scenario" --rate 100 --duration 3 --lockstep --lcm-url memq:// \
    --with-tracker --tracker-out "$w/full/rt" --quiet 2>"$w/rt.err" || rc=$?
expect_full cdpr-rt "$rc" "$w/rt.err" "$w/full/rt/timeseries.csv"
rm -rf "$w/full/rt"

# A size limit: the CSV stops at 20 KiB, summary.json (about 1.3 KiB) still fits.
# expect_limited NAME RC ERRFILE DIR
expect_limited() {
    [ "$2" -eq 3 ] || bad "$1: exit $2, expected 3"
    grep -qF "$4/timeseries.csv: write failed: File too large" "$3" ||
        bad "$1: stderr does not name the CSV with 'File too large': $(cat "$3")"
    whole_rows "$4/timeseries.csv" || bad "$1: a torn row"
    grep -qF '"status": "io_error",' "$4/summary.json" ||
        bad "$1: summary.json does not say io_error"
    echo "$1: exit $2, summary $(grep -F '"status"' "$4/summary.json")"
}
rc=0
(trap '' XFSZ; ulimit -f 40; exec "$bin/cdpr-sim" "$scenario" --duration 3 --out "$w/lim/sim" \
    --no-plot --quiet) 2>"$w/sim-lim.err" || rc=$?
expect_limited cdpr-sim "$rc" "$w/sim-lim.err" "$w/lim/sim"
rc=0
(trap '' XFSZ; ulimit -f 40; exec "$bin/cdpr-rt" "$scenario" --rate 100 --duration 3 --lockstep \
    --lcm-url memq:// --with-tracker --tracker-out "$w/lim/rt" --quiet) 2>"$w/rt-lim.err" || rc=$?
expect_limited cdpr-rt "$rc" "$w/rt-lim.err" "$w/lim/rt"

finish
echo "PASS: full device and size limit: exit 3 with the file and strerror, rows whole, summary io_error where it fits"
