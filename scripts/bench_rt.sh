#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Real-time benchmark (docs/realtime.md, "Benchmark at 1 kHz"; docs/performance.md "Implicit
# integrator"): cdpr-rt runs the paper's circle and line on the 50 m model at 1 kHz for
# DURATION seconds (default 60) with 6 x 16, 6 x 32 and 6 x 64 segments, with RKF45 and with
# ROS34PW2 (--integrator: each with the scenario's settings for it, integrator.ros34pw2 for
# the implicit method), each with and without
# SCHED_FIFO + mlockall, the example tracker in-process over memq:// (so the loop is closed and
# the cables move). Prints each run's telemetry and a table.
#   scripts/bench_rt.sh [DURATION] [FILTER]
# FILTER (a regular expression, default: everything) selects runs by their name
# "<scenario>-<segments>-<integrator>-<other|fifo>", e.g. 'circle-32-ros34pw2-fifo'.
# Not part of the tests: timing belongs to the machine. Needs the release build.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
duration=${1:-60}
filter=${2:-.}
cmake --preset release >/dev/null
cmake --build --preset release --target cdpr-rt >/dev/null
dir=build/bench-rt
mkdir -p "$dir"
{
    printf '| scenario | segments | integrator | scheduling | compute median [us] | p99 [us] | max [us] | p99 / period | deadline misses | trial-limit periods |\n'
    printf '|---|---|---|---|---|---|---|---|---|---|\n'
} > "$dir/table.md"
for sc in circle line; do
    for n in 16 32 64; do
        for integ in rkf45 ros34pw2; do
            base="$dir/$sc-$n.yaml"
            sed "s/^  segments: .*/  segments: $n/" "scenarios/paper-$sc.yaml" > "$base"
            for rt in "" "--realtime"; do
                if [ -n "$rt" ]; then name="$sc-$n-$integ-fifo"; else name="$sc-$n-$integ-other"; fi
                echo "$name" | grep -Eq "$filter" || continue
                log="$dir/run-$name.txt"
                build/release/apps/cdpr-rt "$base" --rate 1000 --duration "$duration" --integrator "$integ" \
                    --lcm-url memq:// --with-tracker $rt > "$log" 2>&1 || true
                awk -v sc="$sc" -v n="$n" -v integ="$integ" '
                    /^  mode/ { sched = ($0 ~ /SCHED_FIFO/) ? "SCHED_FIFO + mlockall" : "SCHED_OTHER" }
                    /compute time/ { med = $7; p99 = $9; max = $11; pct = substr($12, 2) }
                    /deadline misses/ { miss = $3 }
                    /accuracy bound/ { lim = $3 }
                    END { printf "| %s | 6 x %s | %s | %s | %s | %s | %s | %s %% | %s | %s |\n", sc, n, integ, sched, med, p99, max, pct, miss, lim }
                ' "$log" >> "$dir/table.md"
            done
        done
    done
done
cat "$dir"/run-*.txt
echo
cat "$dir/table.md"
