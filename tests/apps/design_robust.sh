#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# design_robust_refuses (tests/apps/CMakeLists.txt): paper-line-hold with tension_filter_s 0.05
# (its setting before issue 22) -> cdpr-design --verdict refuses it at the line's end with 20 %
# more EA (the 20.6 Hz axial mode grows), exit 5.
# usage: design_robust.sh CDPR_DESIGN SOURCE_DIR WORK_DIR
set -eu
design=$1
src=$2
w=$3
rm -rf "$w"
mkdir -p "$w"
sed 's/^  tension_filter_s: 0\.2 .*$/  tension_filter_s: 0.05/' "$src/scenarios/paper-line-hold.yaml" \
    > "$w/old-hold.yaml"
grep -q '^  tension_filter_s: 0.05$' "$w/old-hold.yaml" ||
    { echo "FAIL: the scenario copy does not hold tension_filter_s 0.05"; exit 1; }
rc=0
"$design" "$w/old-hold.yaml" --verdict > "$w/out.txt" 2>&1 || rc=$?
cat "$w/out.txt"
[ "$rc" -eq 5 ] || { echo "FAIL: exit $rc, expected 5 (refused)"; exit 1; }
grep -q "grows at .* at end (t = 10 s), plant EA +20 % (case 16 of the robustness set.s 21;" \
    "$w/out.txt" || { echo "FAIL: the refusal does not name the case"; exit 1; }
# The same case in the table, marked, after 15 stable ones: the check stops at the first refusal.
[ "$(grep -c 'REFUSED$' "$w/out.txt")" -eq 1 ] || { echo "FAIL: not exactly one refused case"; exit 1; }
[ "$(grep -c '^  \(start\|middle\|end\) (t = ' "$w/out.txt")" -eq 16 ] ||
    { echo "FAIL: not 16 cases in the table"; exit 1; }
grep -q "^  end (t = 10 s), plant EA +20 % .*REFUSED$" "$w/out.txt" ||
    { echo "FAIL: the table does not mark the case"; exit 1; }
echo "OK: refused at the line's end with 20 % more EA"
