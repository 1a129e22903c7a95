#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# The figures of a run (scripts/plot_sim.gp, docs/scenarios.md "Outputs"): for the paper's
# circle (one lap), the paper's line and a user's robot file, cdpr-sim writes the expected set,
# every PNG with its PDF (a vector twin), names that say "figure4"/"figure5" only for the
# paper's robot, a laps figure for a single lap, and nothing on stderr but its own note about
# --duration (no gnuplot warning).
# Usage: figures.sh CDPR_SIM SOURCE_DIR WORK_DIR     (exit 77: skipped, no gnuplot)
set -eu
sim=$1
src=$2
w=$3
command -v gnuplot >/dev/null || { echo "SKIPPED: gnuplot not found"; exit 77; }
rm -rf "$w"
mkdir -p "$w"
fail=0
run() { # NAME SCENARIO DURATION EXPECTED...
    name=$1
    scen=$2
    dur=$3
    shift 3
    "$sim" "$src/scenarios/$scen" --out "$w/$name" --duration "$dur" --quiet 2>"$w/$name.err" ||
        { cat "$w/$name.err"; echo "FAIL: $name: cdpr-sim exited $?"; fail=1; return; }
    if grep -v -e "^cdpr-sim: --duration $dur s overrides run.duration_s" "$w/$name.err" >/dev/null; then
        cat "$w/$name.err"
        echo "FAIL: $name: stderr holds more than the --duration note"
        fail=1
    fi
    got=$(cd "$w/$name" && ls *.png | sed 's/\.png$//' | sort | tr '\n' ' ')
    want=$(printf '%s\n' "$@" | sort | tr '\n' ' ')
    [ "$got" = "$want" ] || { echo "FAIL: $name: figures '$got', expected '$want'"; fail=1; }
    for f in "$w/$name"/*.png; do
        pdf=${f%.png}.pdf
        if [ ! -s "$f" ] || [ "$(head -c 5 "$pdf" 2>/dev/null)" != "%PDF-" ]; then
            echo "FAIL: $name: $f without a PDF twin"
            fail=1
        fi
    done
    [ $fail -ne 0 ] || echo "ok   $name: $want (PNG and PDF), stderr clean"
}
run paper-circle paper-circle.yaml 6.3 figure4 errors tensions cables laps
run paper-line paper-line.yaml 1 figure5 tensions cables
run rig-circle example-rig-circle.yaml 1 path errors tensions cables
[ $fail -eq 0 ] || exit 1
echo "PASS: every figure as PNG and PDF, paper names for the paper's robot only, no warnings"
