#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Real-time benchmark (docs/realtime.md, "Benchmark at 1 kHz"): cdpr-rt runs the paper's circle
# on the 50 m model at 1 kHz for DURATION seconds (default 60) with 6 x 16 and 6 x 32
# segments, each with and without SCHED_FIFO + mlockall, the example tracker in-process over
# memq:// (so the loop is closed and the cables move). Prints each run's telemetry and a table.
# Not part of the tests: timing belongs to the machine. Needs the release build.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
duration=${1:-60}
cmake --preset release >/dev/null
cmake --build --preset release --target cdpr-rt >/dev/null
dir=build/bench-rt
mkdir -p "$dir"
{
    printf '| segments | scheduling | compute median [us] | p99 [us] | max [us] | p99 / period | deadline misses | trial-limit periods |\n'
    printf '|---|---|---|---|---|---|---|---|\n'
} > "$dir/table.md"
for n in 16 32; do
    sed "s/^  segments: .*/  segments: $n/" scenarios/paper-circle.yaml > "$dir/circle-$n.yaml"
    for rt in "" "--realtime"; do
        log="$dir/run-$n${rt:+-fifo}.txt"
        build/release/apps/cdpr-rt "$dir/circle-$n.yaml" --rate 1000 --duration "$duration" \
            --lcm-url memq:// --with-tracker $rt > "$log" 2>&1
        awk -v n="$n" '
            /^  mode/ { sched = ($0 ~ /SCHED_FIFO/) ? "SCHED_FIFO + mlockall" : "SCHED_OTHER" }
            /compute time/ { med = $7; p99 = $9; max = $11; pct = substr($12, 2) }
            /deadline misses/ { miss = $3 }
            /accuracy bound/ { lim = $3 }
            END { printf "| 6 x %s | %s | %s | %s | %s | %s %% | %s | %s |\n", n, sched, med, p99, max, pct, miss, lim }
        ' "$log" >> "$dir/table.md"
    done
done
cat "$dir"/run-*.txt
echo
cat "$dir/table.md"
