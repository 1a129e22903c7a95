#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Plant and controller on "two machines": two network namespaces joined by a veth pair, the
# way two hosts on one Ethernet segment are joined (docs/realtime.md, "Two machines"):
#   namespace P (this shell; run_in_netns.sh made it):  cdpr-rt,      veth-plant 10.76.67.1/24
#   namespace C (unshare -n, entered with nsenter):      cdpr-tracker, veth-ctl   10.76.67.2/24
# Each side routes multicast (224.0.0.0/4) out of its veth, LCM's URL has ttl=1, and nothing
# is ever configured in the host's own namespace: both namespaces (and the veth pair, created
# inside P) vanish with the test. Then
#  1. lockstep: the tracker's view of the run must equal the one-process batch run (cdpr-sim,
#     same scenario, rate and duration) bit for bit, every row but the last (as loop_udpm.sh);
#  2. free-running: the plant must accept the controller's commands across the link;
#  3. the datagrams really crossed the veth pair (its packet counters).
# Usage (inside run_in_netns.sh): two_hosts.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -eu
bin=$1/apps
src=$2
w=$3
scenario=$src/scenarios/paper-line.yaml
url='udpm://239.255.76.67:7667?ttl=1'
rm -rf "$w"
mkdir -p "$w"
skip() {
    echo "SKIPPED: $*"
    exit 77
}
fail() {
    echo "FAIL: $*"
    exit 1
}
command -v nsenter >/dev/null 2>&1 || skip "'nsenter' not found (Debian: util-linux)"

# Namespace C: a process that only holds it open.
unshare -n sleep 300 &
holder=$!
trap 'kill "$holder" 2>/dev/null || true' EXIT
sleep 0.2
in_c() {
    nsenter -t "$holder" -n "$@"
}
in_c true || skip "cannot enter a second network namespace (nsenter -n)"
ip link add veth-plant type veth peer name veth-ctl || skip "cannot create a veth pair"
ip link set veth-ctl netns "$holder" || skip "cannot move the veth peer into the second namespace"
# P: the loopback route run_in_netns.sh added goes; multicast leaves through the veth.
ip route del 224.0.0.0/4 dev lo 2>/dev/null || true
ip addr add 10.76.67.1/24 dev veth-plant
ip link set veth-plant up
ip route add 224.0.0.0/4 dev veth-plant
in_c sh -c 'ip link set lo up && ip addr add 10.76.67.2/24 dev veth-ctl &&
            ip link set veth-ctl up && ip route add 224.0.0.0/4 dev veth-ctl' ||
    skip "cannot configure the second namespace"
ip route show
in_c ip route show

# 1. Lockstep across the link.
in_c "$bin/cdpr-tracker" "$scenario" --rate 100 --duration 1 --lcm-url "$url" \
    --out "$w/tracker" --no-plot --quiet &
tracker=$!
sleep 0.5
"$bin/cdpr-rt" "$scenario" --rate 100 --duration 1 --lockstep --max-trials 2000 \
    --lcm-url "$url" > "$w/rt.txt"
wait "$tracker" || fail "cdpr-tracker (namespace C) failed"
cat "$w/rt.txt"
grep -q "0 timeouts" "$w/rt.txt" || fail "lockstep timeouts across the veth pair"
"$bin/cdpr-sim" "$scenario" --out "$w/sim" --duration 1 --no-plot --quiet
head -n 101 "$w/sim/timeseries.csv" > "$w/sim.csv"
head -n 101 "$w/tracker/timeseries.csv" > "$w/tracker.csv"
[ "$(wc -l < "$w/sim.csv")" -eq 101 ] || fail "cdpr-sim wrote too few rows"
cmp "$w/sim.csv" "$w/tracker.csv" || fail "the two-namespace lockstep run differs from the one-process run"
echo "PASS: lockstep across two namespaces == one-process run, 100 periods bit for bit"

# 2. Free-running across the link.
in_c "$bin/cdpr-tracker" "$scenario" --rate 100 --duration 1 --lcm-url "$url" \
    --out "$w/tracker-free" --no-plot --quiet &
tracker=$!
sleep 0.5
"$bin/cdpr-rt" "$scenario" --rate 100 --duration 1 --max-trials 2000 --lcm-url "$url" \
    > "$w/rt-free.txt"
wait "$tracker" || true # the tracker may wait for states after the plant's end: not an error
cat "$w/rt-free.txt"
accepted=$(sed -n 's/^ *received *\([0-9]*\) accepted.*/\1/p' "$w/rt-free.txt")
[ -n "$accepted" ] && [ "$accepted" -ge 50 ] ||
    fail "free-running: only ${accepted:-?} commands accepted across the link"
echo "PASS: free-running across two namespaces, $accepted commands accepted"

# 3. The traffic went over the veth pair, not a loopback.
# (sysfs shows the host's namespace: read the counters with ip.)
ip -s link show veth-plant > "$w/veth.txt"
cat "$w/veth.txt"
rx=$(awk '/RX:/ { getline; print $2; exit }' "$w/veth.txt")
tx=$(awk '/TX:/ { getline; print $2; exit }' "$w/veth.txt")
[ "$rx" -ge 100 ] && [ "$tx" -ge 100 ] || fail "veth-plant carried only $tx sent / $rx received packets"
echo "PASS: veth-plant carried $tx packets out (states) and $rx in (commands)"
