#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The main job. Installs what is missing, builds the Release configuration, and runs
#  1. the validation case of the foundation: one cable released from the straight chord
#     between two fixed points settles into its sagging shape; mid-span sag and end tensions
#     next to Irvine's elastic catenary for N = 8..64 segments (out/settle/);
#  2. the paper's circle (Duan et al. 2010, §4) over ten laps with the tracking controller
#     (scenarios/paper-circle-laps.yaml: the paper's start 1.47 m below the path, a planned
#     transfer, winch tension feedback and learning over laps) through the real-time loop: cdpr-rt (the plant, 1 kHz periodic thread) and cdpr-tracker (the
#     external controller) as two processes exchanging cabin state, cable tensions and winch
#     commands over LCM UDP multicast on loopback, recorded by lcm-logger. The plant integrates
#     in the fixed-cost mode (ROS34PW2 in n equal substeps per 1 ms period, n derived from the
#     model: the same work in every period; docs/realtime.md "Real-time contract"). When multicast
#     cannot be set up, both sides run in one process over memq:// instead, and it says so.
#     Writes out/paper-circle-rt/ (timeseries.csv, summary.json, figure4, errors, tensions,
#     cables and laps as .png and .pdf, laps.csv, circle.lcmlog) and prints the tracking summary (with
#     the RMS error of every lap) and the plant telemetry; about 65 s;
#  3. the paper's line (scenarios/paper-line.yaml, feed-forward alone, batch run: out/paper-line/)
#     next to the same line with the length pre-compensation (scenarios/paper-line-precomp.yaml
#     and its correction, made offline by cdpr-precomp) through the real-time loop, cdpr-rt +
#     cdpr-tracker over the same URL as 2 (or memq://) at the scenario's 100 Hz
#     (out/paper-line-precomp-rt/); a table of the two (error after 2 s, tension) and their
#     errors in one figure, out/paper-line-compare.png/.pdf (scripts/compare_runs.py); 15 s;
#  4. a redundant robot: the paper's line on eight cables (robots/eight-50m.yaml,
#     scenarios/eight-line.yaml: the redundancy resolved by the robot's tension distribution)
#     through the real-time loop, cdpr-rt + cdpr-tracker over the same URL as 2 (or memq://)
#     at the scenario's 100 Hz, eight values in every command; out/eight-line-rt/; 15 s.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh

cmake --preset release >/dev/null
cmake --build --preset release --target cdpr-settle cdpr-sim cdpr-rt cdpr-tracker

out=out/settle
mkdir -p "$out"
build/release/apps/cdpr-settle --out "$out"
gnuplot -e "dir='$out'" scripts/plot_settle.gp
echo "plot: $out/settled_shape.png"

bin=build/release/apps

# Wait until cdpr-tracker (pid $1, stderr in $2) listens: 0 when it does, 1 when it exits or
# 60 s pass. The plant starts only then, so that the tracker sees state 0.
wait_for_tracker() {
    for _ in $(seq 600); do
        grep -q "waiting for" "$2" 2>/dev/null && return 0
        kill -0 "$1" 2>/dev/null || break
        sleep 0.1
    done
    grep -q "waiting for" "$2" 2>/dev/null
}

scenario=scenarios/paper-circle-laps.yaml
out=out/paper-circle-rt
rm -rf "$out"
mkdir -p "$out"
url='udpm://239.255.76.67:7667?ttl=0'
echo
echo "==== $scenario: closed loop over LCM at 1 kHz (cdpr-rt + cdpr-tracker)"
# udpm on loopback needs a multicast route through lo (docs/development.md, platform notes).
multicast=1
if ! ip route show table all 2>/dev/null | grep -q '^multicast 224.0.0.0/4\|^224.0.0.0/4'; then
    if ! ip route add 224.0.0.0/4 dev lo 2>/dev/null; then
        multicast=0
        why="cannot add the multicast route 224.0.0.0/4 via lo (not root, or no ip tool)"
    fi
fi
if [[ $multicast -eq 1 ]]; then
    lcm-logger --lcm-url="$url" --quiet "$out/circle.lcmlog" &
    logger=$!
    sleep 0.3
    if ! kill -0 "$logger" 2>/dev/null; then
        multicast=0
        why="lcm-logger could not open $url"
    fi
fi
if [[ $multicast -eq 1 ]]; then
    echo "two processes over $url; lcm-logger records to $out/circle.lcmlog"
    # Start the plant only once the tracker listens, so that it sees state 0. (The
    # controller's design is checked by the tests' design_gate_paper-circle-laps, not here:
    # cdpr-design scenarios/paper-circle-laps.yaml --verdict, its 21-case robustness set,
    # ~25 s.)
    "$bin/cdpr-tracker" "$scenario" --rate 1000 --integrator ros34pw2-fixed --lcm-url "$url" --out "$out" \
        2> >(tee "$out/tracker.stderr" >&2) &
    tracker=$!
    if ! wait_for_tracker "$tracker" "$out/tracker.stderr"; then
        kill -INT "$logger" 2>/dev/null || true
        echo "demo: cdpr-tracker did not come up (see $out/tracker.stderr)"
        exit 1
    fi
    status=0
    "$bin/cdpr-rt" "$scenario" --rate 1000 --integrator ros34pw2-fixed --lcm-url "$url" --start-delay 0.5 --realtime \
        || status=$?
    wait "$tracker" || status=$?
    sleep 0.2
    kill -INT "$logger" 2>/dev/null || true
    wait "$logger" 2>/dev/null || true
    [[ $status -eq 0 ]] || { echo "demo: the closed loop failed (exit $status)"; exit "$status"; }
else
    echo "NOTE: UDP multicast unavailable ($why):"
    echo "      running plant and tracker in one process over memq:// instead"
    "$bin/cdpr-rt" "$scenario" --rate 1000 --integrator ros34pw2-fixed --lcm-url memq:// --realtime --with-tracker \
        --tracker-out "$out"
fi
echo "figures: $out/figure4.png, $out/errors.png, $out/tensions.png (one panel per cable), $out/cables.png, $out/laps.png (error per lap); each also as .pdf"

# The closed loop of scenario $1 over LCM at its own rate (cdpr-tracker + cdpr-rt on $url, or
# one process over memq:// without multicast), outputs in $2.
rt_loop() {
    local scen=$1 dir=$2 status=0
    rm -rf "$dir"
    mkdir -p "$dir"
    if [[ $multicast -eq 1 ]]; then
        "$bin/cdpr-tracker" "$scen" --lcm-url "$url" --out "$dir" \
            2> >(tee "$dir/tracker.stderr" >&2) &
        local tracker=$!
        wait_for_tracker "$tracker" "$dir/tracker.stderr" ||
            { echo "demo: cdpr-tracker did not come up (see $dir/tracker.stderr)"; exit 1; }
        "$bin/cdpr-rt" "$scen" --lcm-url "$url" --start-delay 0.5 --realtime || status=$?
        wait "$tracker" || status=$?
        [[ $status -eq 0 ]] || { echo "demo: the loop of $scen failed (exit $status)"; exit "$status"; }
    else
        "$bin/cdpr-rt" "$scen" --lcm-url memq:// --realtime --with-tracker --tracker-out "$dir"
    fi
}

echo
echo "==== the paper's line: feed-forward alone (scenarios/paper-line.yaml, batch run) and with"
echo "     the length pre-compensation (scenarios/paper-line-precomp.yaml) over LCM at 100 Hz"
"$bin/cdpr-sim" scenarios/paper-line.yaml --out out/paper-line
rt_loop scenarios/paper-line-precomp.yaml out/paper-line-precomp-rt
/usr/bin/python3 scripts/compare_runs.py --after 2 --out out/paper-line-compare \
    "feed-forward alone=out/paper-line" \
    "with the pre-compensation (real-time loop)=out/paper-line-precomp-rt"

echo
echo "==== scenarios/eight-line.yaml: eight cables, closed loop over LCM at 100 Hz"
rt_loop scenarios/eight-line.yaml out/eight-line-rt
echo "figures: out/eight-line-rt/errors.png, out/eight-line-rt/tensions.png (eight panels), out/eight-line-rt/cables.png; each also as .pdf"
