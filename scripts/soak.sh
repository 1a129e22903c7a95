#!/bin/bash
# SPDX-License-Identifier: BSD-3-Clause
# Soak run (not in CI; docs/performance.md "Soak"): cdpr-sim on a cyclic scenario for its full
# duration (scenarios/soak-deploy-retrieve.yaml: 150 deploy/retrieve cycles, 3600 s of plant
# time), sampling the process's resident memory (VmRSS of /proc/PID/status) while it runs, then
# a table per cycle from timeseries.csv: node insertions and removals (rises and falls of the
# segment counts n1..n6), the winches' work on the cables (the integral of -T_winch u over the
# cycle: energy the winches put in, which the cable damping and drag dissipate), the largest
# position error, and the wall time the cycle took (from the --progress lines), so a drift of
# any of them over the hour shows.
#
# usage: scripts/soak.sh [--sim PATH] [--scenario FILE] [--out DIR] [--duration S] [--every S]
#   --sim       cdpr-sim to run (default: build/release/apps/cdpr-sim, else build/debug/...)
#   --scenario  a scenario with trajectory.type cyclic (default scenarios/soak-deploy-retrieve.yaml)
#   --out       output directory (default build/soak)
#   --duration  plant time [s] (default: the scenario's run.duration_s)
#   --every     RSS sampling interval [s] of wall time (default 5)
#   --no-run    only the table, from the outputs of an earlier run in --out
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
sim=""
scenario="$here/scenarios/soak-deploy-retrieve.yaml"
out="$here/build/soak"
duration=""
every=5
run=1
while [ $# -gt 0 ]; do
    case "$1" in
    --sim) sim=$2; shift 2 ;;
    --scenario) scenario=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --duration) duration=$2; shift 2 ;;
    --every) every=$2; shift 2 ;;
    --no-run) run=0; shift ;;
    *) echo "soak.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
if [ "$run" -eq 1 ]; then
    if [ -z "$sim" ]; then
        for c in "$here/build/release/apps/cdpr-sim" "$here/build/debug/apps/cdpr-sim"; do
            if [ -x "$c" ]; then sim=$c; break; fi
        done
    fi
    [ -x "$sim" ] || { echo "soak.sh: no cdpr-sim (build one, or give --sim)" >&2; exit 2; }
    mkdir -p "$out"
    args=("$scenario" --out "$out/run" --no-plot --progress)
    [ -n "$duration" ] && args+=(--duration "$duration")
    echo "soak.sh: $sim ${args[*]}"
    date +%s.%N >"$out/start.txt"
    "$sim" "${args[@]}" >"$out/stdout.txt" 2>"$out/progress.txt" &
    pid=$!
    : >"$out/rss.txt"
    while kill -0 "$pid" 2>/dev/null; do
        rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
        [ -n "$rss" ] && echo "$(date +%s.%N) $rss" >>"$out/rss.txt"
        sleep "$every"
    done
    wait "$pid"
    rc=$?
    echo "soak.sh: cdpr-sim exit $rc"
    [ "$rc" -eq 0 ] || { cat "$out/progress.txt" >&2; exit "$rc"; }
fi
start=$(cat "$out/start.txt")
python3 - "$out" "$scenario" "$start" <<'PY'
import csv, json, math, re, sys
out, scenario, start = sys.argv[1], sys.argv[2], float(sys.argv[3])
# The cycle of the scenario (trajectory.cyclic: 2 (duration_s + pause_s)).
text = open(scenario).read()
blk = text[text.index('cyclic:', text.index('type: cyclic') + 12):]
leg = float(re.search(r'duration_s:\s*([0-9.eE+-]+)', blk).group(1))
pause = float(re.search(r'pause_s:\s*([0-9.eE+-]+)', blk).group(1))
P = 2.0 * (leg + pause)
rows = csv.DictReader(l for l in open(out + '/run/timeseries.csv') if not l.startswith('#'))
cyc = {}
prev = None
cyc0 = None
for r in rows:
    t = float(r['t_s'])
    k = int(math.floor(t / P + 1e-9))
    c = cyc.setdefault(k, {'ins': 0, 'rem': 0, 'work': 0.0, 'err': 0.0})
    n = [int(float(r['n%d' % j])) for j in range(1, 7)]
    if cyc0 is None:
        cyc0 = n
    if prev is not None:
        dt = t - prev[0]
        for j in range(6):
            d = n[j] - prev[1][j]
            c['ins'] += max(d, 0)
            c['rem'] += max(-d, 0)
            # work the winch does on cable j over the row (u > 0 pays out: the cable pulls the
            # drum, the winch absorbs T u); rectangle rule with the previous row's values.
            c['work'] += -prev[2][j] * prev[3][j] * dt
    c['err'] = max(c['err'], float(r['epos_m']))
    prev = (t, n, [float(r['T_winch%d_N' % j]) for j in range(1, 7)],
            [float(r['u%d_m_per_s' % j]) for j in range(1, 7)])
# Wall time of each cycle from the progress lines "t = T / ... (x real time)" (one per 5 s).
prog = []
for l in open(out + '/progress.txt'):
    m = re.search(r't = ([0-9.]+) / .*, ([0-9.]+)x real time', l)
    if m:
        t = float(m.group(1))
        prog.append((t, t / float(m.group(2)) if float(m.group(2)) > 0 else 0.0))
def wall_at(t):
    for i in range(1, len(prog)):
        if prog[i][0] >= t:
            (t0, w0), (t1, w1) = prog[i - 1], prog[i]
            return w0 + (w1 - w0) * (t - t0) / (t1 - t0) if t1 > t0 else w1
    return float('nan')
rss = [tuple(map(float, l.split())) for l in open(out + '/rss.txt') if l.strip()]
def rss_at(w):
    best = None
    for (ts, kb) in rss:
        if ts - start <= w:
            best = kb
    return best
summ = json.load(open(out + '/run/summary.json'))
full = [k for k in sorted(cyc) if (k + 1) * P <= summ['sim_time_s'] + 1e-9]
print('| cycle | t end [s] | insertions | removals | winch work [kJ] | max error [mm] | wall [s] | RSS [kB] |')
print('|---:|---:|---:|---:|---:|---:|---:|---:|')
show = full if len(full) <= 12 else full[:5] + full[len(full) // 2:len(full) // 2 + 1] + full[-5:]
for k in show:
    c = cyc[k]
    w1 = wall_at((k + 1) * P)
    w0 = wall_at(k * P) if k > 0 else 0.0
    r = rss_at(w1) if not math.isnan(w1) else None
    print('| %d | %.0f | %d | %d | %.3f | %.2f | %.2f | %s |' % (k + 1, (k + 1) * P, c['ins'], c['rem'],
          c['work'] / 1e3, 1e3 * c['err'], w1 - w0, '%d' % r if r else 'n/a'))
ins = [cyc[k]['ins'] for k in full[1:]]
rem = [cyc[k]['rem'] for k in full[1:]]
work = [cyc[k]['work'] for k in full[1:]]
walls = [wall_at((k + 1) * P) - wall_at(k * P) for k in full[1:]]
walls = [w for w in walls if not math.isnan(w)]
kb = [x[1] for x in rss]
print()
print('cycles %d (P = %g s), plant time %g s, wall %.1f s (%.1fx real time)' % (len(full), P,
      summ['sim_time_s'], summ['wall_time_s'], summ['sim_time_s'] / summ['wall_time_s']))
print('summary: status %s, node_insertions %d, node_removals %d, max_error_m %.4g, ik_failures %d, substep_limit_hits %d'
      % (summ['status'], summ['node_insertions'], summ['node_removals'], summ['max_error_m'],
         summ['ik_failures'], summ['substep_limit_hits']))
if ins:
    print('cycles 2..%d: insertions per cycle %d..%d, removals per cycle %d..%d' % (len(full), min(ins), max(ins), min(rem), max(rem)))
    print('winch work per cycle: %.4f .. %.4f kJ (first of them %.4f, last %.4f)' % (min(work) / 1e3, max(work) / 1e3, work[0] / 1e3, work[-1] / 1e3))
print('segments per cable: first row %s, last row %s' % (cyc0, prev[1]))
if len(walls) >= 4:
    q = len(walls) // 4
    a, b = sum(walls[:q]) / q, sum(walls[-q:]) / q
    print('wall time per cycle: first quarter %.3f s, last quarter %.3f s (drift %+.1f %%)' % (a, b, 100.0 * (b - a) / a))
if kb:
    print('RSS: %d samples, first %d kB, min %d kB, max %d kB, last %d kB' % (len(kb), kb[0], min(kb), max(kb), kb[-1]))
PY
