#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# MISRA C:2012 check of the firmware code (lib/core and lib/control) with cppcheck's misra addon.
#
#   scripts/misra.sh            check: non-zero when a rule not in the deviation table of
#                               docs/misra.md is violated, or a deviated rule's count grew
#   scripts/misra.sh --update   also rewrite the count column of that table with the counts
#                               found (after a reviewed change; a new rule still needs a row
#                               and a reason written by hand)
#
# Outputs: build/misra/report.txt (every finding, file:line:column), build/misra/counts.txt
# (per rule: found, allowed, verdict; also printed). The addon ships without the licensed rule
# texts, so findings name the rule number only. The configuration checked is the double build
# of the Cortex-M7 (CDPR_REAL_IS_FLOAT undefined, default capacities) on a 32-bit platform,
# C99, the headers in lib/core/include, lib/core/src and lib/control/include.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

update=0
if [[ ${1:-} == --update ]]; then
    update=1
elif [[ $# -gt 0 ]]; then
    echo "usage: $0 [--update]" >&2
    exit 2
fi

doc=docs/misra.md
out=build/misra
mkdir -p "$out"
# cppcheck writes its dump files (the addon's input) into the build dir rather than next to
# the sources; a fresh one each run, so no cached result can hide a finding.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Debian's cppcheck runs the addon with this interpreter (the python3 first on PATH may be
# another build); the addon needs only the standard library.
python=/usr/bin/python3
[[ -x $python ]] || python=python3

# The same file sets as lib/core/ and lib/control/CMakeLists.txt (globs of src/*.c).
sources=(lib/core/src/*.c lib/control/src/*.c)
# One invocation for all sources: the rules about the whole program (8.7, 5.7, 2.5 ...) need
# every translation unit. cppcheck prints findings on stderr; without --error-exitcode it
# exits 0 on findings and non-zero only when it could not run.
# cdpr/version.h is generated at configure time (cmake/version.h.in); the check needs no
# build tree, so it writes its own copy with placeholder numbers.
mkdir -p "$work/gen/cdpr"
sed -e 's/@CDPR_VERSION_MAJOR@/0/; s/@CDPR_VERSION_MINOR@/0/; s/@CDPR_VERSION_PATCH@/0/' \
    -e 's/@CDPR_VERSION@/0.0.0/; s/@CDPR_GIT_DESCRIBE@/misra/' cmake/version.h.in \
    >"$work/gen/cdpr/version.h"
# cdpr/build_config.h likewise, with the default capacities of a double build.
sed -e 's/@CDPR_MAX_CABLES@/8/; s/@CDPR_MAX_SEGMENTS@/64/; s/@CDPR_BUILD_REAL_IS_FLOAT@/0/' \
    cmake/build_config.h.in >"$work/gen/cdpr/build_config.h"
cppcheck --addon=misra --addon-python="$python" --std=c99 --language=c --platform=unix32 \
    -UCDPR_REAL_IS_FLOAT \
    -I lib/core/include -I lib/core/src -I lib/control/include -I "$work/gen" \
    --cppcheck-build-dir="$work" --quiet \
    --template='{file}:{line}:{column}: {severity}: {id}: {message}' \
    "${sources[@]}" 2>"$out/report.txt"

# Rule of each finding: misra-c2012-15.5 -> 15.5; anything else (misra-config, a cppcheck
# error such as syntaxError) is kept under its own id and, having no row, fails the check.
awk -F': ' '/^[^ ].*:[0-9]+:[0-9]+: / {id = $3; sub(/^misra-c2012-/, "", id); print id}' \
    "$out/report.txt" | sort | uniq -c | awk '{print $2, $1}' >"$work/found"

# Deviation table: the rows "| rule | count | ..." between the markers in docs/misra.md.
awk -F'|' '/<!-- misra-deviations:begin -->/ {on = 1; next}
           /<!-- misra-deviations:end -->/ {on = 0}
           on && $2 ~ /^ *[0-9]+\.[0-9]+ *$/ {gsub(/ /, "", $2); gsub(/ /, "", $3); print $2, $3}' \
    "$doc" >"$work/allowed"
if [[ ! -s $work/allowed ]]; then
    echo "misra: no deviation table found in $doc" >&2
    exit 1
fi

# found/allowed per rule -> verdict. "fewer" passes (run --update to lock the gain in).
awk 'FNR == NR {allowed[$1] = $2; next} {found[$1] = $2}
     END {
         for (r in allowed) rules[r] = 1
         for (r in found) rules[r] = 1
         for (r in rules) {
             f = (r in found) ? found[r] : 0
             if (!(r in allowed)) v = "NEW: not a documented deviation"
             else if (f > allowed[r]) v = "GREW: above the documented count"
             else if (f < allowed[r]) v = "fewer (--update records it)"
             else v = "ok"
             printf "%s %d %s %s\n", r, f, (r in allowed) ? allowed[r] : "-", v
         }
     }' "$work/allowed" "$work/found" | sort -V >"$work/table"
{
    printf '%-12s %6s %8s  %s\n' rule found allowed verdict
    awk '{v = $4; for (i = 5; i <= NF; ++i) v = v " " $i; printf "%-12s %6d %8s  %s\n", $1, $2, $3, v}' \
        "$work/table"
    awk '{f += $2} END {printf "%-12s %6d\n", "total", f}' "$work/table"
} | tee "$out/counts.txt"
echo "misra: full report in $out/report.txt"

failing='NEW|GREW'
if [[ $update -eq 1 ]]; then
    # Rewrite only the count column of existing rows; rules no longer found get 0.
    tr ' ' '|' <"$work/found" >"$work/found.psv"
    awk -F'|' -v OFS='|' 'FNR == NR {found[$1] = $2; next}
         /<!-- misra-deviations:begin -->/ {on = 1}
         /<!-- misra-deviations:end -->/ {on = 0}
         on && $2 ~ /^ *[0-9]+\.[0-9]+ *$/ {
             r = $2; gsub(/ /, "", r); $3 = " " ((r in found) ? found[r] : 0) " "
         }
         {print}' "$work/found.psv" "$doc" >"$work/doc"
    cp "$work/doc" "$doc"
    echo "misra: counts in $doc updated"
    failing='NEW'
fi

if grep -qE " ($failing):" "$work/table"; then
    echo "misra: FAILED (new rule or grown count: fix the code, or document the deviation in $doc)" >&2
    exit 1
fi
echo "misra: OK (every finding is a documented deviation within its count)"
