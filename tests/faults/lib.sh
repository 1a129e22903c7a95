# SPDX-License-Identifier: BSD-3-Clause
# Shared by the fault scripts (sourced): arguments, a fresh work directory, fail() (stop at
# the first failed check) or bad() + finish (go on, fail at the end), and the helpers to read
# a value off cdpr-rt's telemetry block.
# Usage in a script: . "$(dirname "$0")/lib.sh" "$@"   (BUILD_DIR SOURCE_DIR WORK_DIR)
bin=$1/apps
src=$2
w=$3
url='udpm://239.255.76.67:7667?ttl=0'
rm -rf "$w"
mkdir -p "$w"
# A script that stops early (a failed check, set -e) leaves no process behind: its
# background apps are killed on exit (a tracker that never saw a state would wait forever).
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT
fail() {
    echo "FAIL: $*"
    exit 1
}
# bad WHAT: a failed check that lets the script go on; finish exits 1 after any.
failures=0
bad() {
    echo "FAIL: $*"
    failures=$((failures + 1))
}
finish() {
    [ "$failures" -eq 0 ] || exit 1
}
# whole_rows CSV: every data row (and the header) has the header's field count.
whole_rows() {
    awk -F, '!/^#/ { if (n == 0) n = NF; else if (NF != n) { print "row " NR ": " NF " of " n " fields"; bad = 1 } }
             END { exit bad }' "$1"
}
# expect_exit WANT GOT WHAT
expect_exit() {
    [ "$2" -eq "$1" ] || fail "$3: exit code $2, expected $1"
}
# first number after a label on a telemetry line: num FILE LABEL [FIELD-AFTER-LABEL]
num() {
    sed -n "s/^  $2 *\([0-9][0-9]*\).*/\1/p" "$1" | head -n 1
}
# the number just before a word on a telemetry line: before FILE LABEL WORD
before() {
    grep "^  $2 " "$1" | head -n 1 | sed -n "s/.* \([0-9][0-9]*\) $3.*/\1/p"
}
# wait_for FILE PATTERN SECONDS: until FILE has a line matching PATTERN (grep -E), or fail.
wait_for() {
    n=0
    while ! grep -Eq "$2" "$1" 2>/dev/null; do
        n=$((n + 1))
        [ "$n" -le $(($3 * 20)) ] || fail "no '$2' in $1 within $3 s"
        sleep 0.05
    done
}
# python_or_skip: $py = the Python with LCM's module and this build's message types, or exit 77.
python_or_skip() {
    py=${CDPR_PYTHON3:-/usr/bin/python3}
    if ! "$py" -c 'import lcm, cdpr.winch_command_t' 2> "$w/import.txt"; then
        cat "$w/import.txt"
        echo "SKIPPED: LCM's Python module is not importable (PYTHONPATH=${PYTHONPATH:-})"
        exit 77
    fi
}
# tracker_then_plant SCENARIO OPTIONS: cdpr-tracker (output in $w/t.txt, pid $t), then a
# free-running cdpr-rt with a 0.1 s watchdog ($w/rt.txt, $w/rt.err, pid $rt); returns once the
# plant runs. OPTIONS (one word list) go to both.
tracker_then_plant() {
    "$bin/cdpr-tracker" "$1" $2 --quiet --idle-exit 30 > "$w/t.txt" 2>&1 &
    t=$!
    sleep 0.5
    "$bin/cdpr-rt" "$1" $2 --watchdog 0.1 > "$w/rt.txt" 2> "$w/rt.err" &
    rt=$!
    wait_for "$w/rt.err" "running" 60
}
