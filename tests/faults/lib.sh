# SPDX-License-Identifier: BSD-3-Clause
# Shared by the fault scripts (sourced): arguments, a fresh work directory, fail(), and the
# helpers to read a value off cdpr-rt's telemetry block.
# Usage in a script: . "$(dirname "$0")/lib.sh" "$@"   (BUILD_DIR SOURCE_DIR WORK_DIR)
bin=$1/apps
src=$2
w=$3
url='udpm://239.255.76.67:7667?ttl=0'
rm -rf "$w"
mkdir -p "$w"
fail() {
    echo "FAIL: $*"
    exit 1
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
