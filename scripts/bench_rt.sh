#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Real-time benchmark (docs/realtime.md, "Benchmark at 1 kHz"; docs/performance.md "Implicit
# integrator"): cdpr-rt runs the paper's circle and line on the 50 m model at 1 kHz for
# DURATION seconds (default 60) with 6 x 16, 6 x 32 and 6 x 64 segments, with RKF45 (the
# scenario's own settings) and with ROS34PW2 (integrator.method: ros34pw2 and the implicit
# tolerances of docs/model.md §7 in a copy of the scenario), each with and without
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
# The implicit run's integrator section: loose node tolerances (the stiff axial modes are
# damped, not resolved), at most 4 trials per period.
ros_section='integrator:\n  method: ros34pw2\n  rtol: 1.0e-3\n  atol_position_m: 1.0e-4\n  atol_velocity_m_per_s: 1.0e-2\n  atol_quaternion: 1.0e-6\n  atol_rate_rad_per_s: 1.0e-4\n  h_max_s: 0.01\n  max_trials: 4\n'
for sc in circle line; do
    for n in 16 32 64; do
        for integ in rkf45 ros34pw2; do
            base="$dir/$sc-$n-$integ.yaml"
            sed "s/^  segments: .*/  segments: $n/" "scenarios/paper-$sc.yaml" > "$base"
            if [ "$integ" = ros34pw2 ]; then
                # replace the integrator section (up to the next top-level key)
                awk -v sect="$ros_section" '
                    /^integrator:/ { printf "%s", sect; skip = 1; next }
                    skip && /^[^ #]/ { skip = 0 }
                    !skip { print }
                ' "$base" | sed 's/\\n/\n/g' > "$base.tmp" && mv "$base.tmp" "$base"
            fi
            for rt in "" "--realtime"; do
                if [ -n "$rt" ]; then name="$sc-$n-$integ-fifo"; else name="$sc-$n-$integ-other"; fi
                echo "$name" | grep -Eq "$filter" || continue
                log="$dir/run-$name.txt"
                build/release/apps/cdpr-rt "$base" --rate 1000 --duration "$duration" \
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
