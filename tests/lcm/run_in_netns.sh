#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# Run a test binary inside a private network namespace whose loopback carries IPv4 multicast,
# so LCM's udpm provider works without touching the host's network (docs/development.md, platform notes):
#   unshare -n sh -c 'ip link set lo up; ip route add 224.0.0.0/4 dev lo; exec ./the_test'
# When that is impossible it prints "SKIPPED: <reason>" and exits 77, which ctest reports as
# a skipped test (SKIP_RETURN_CODE 77), never as a pass.
# Usage: run_in_netns.sh <test-binary> [args...]
set -u
skip() {
    echo "SKIPPED: $*"
    exit 77
}
[ $# -ge 1 ] || { echo "usage: $0 <test-binary> [args...]" >&2; exit 2; }
[ "$(id -u)" = 0 ] || skip "udpm loopback test needs root for 'unshare -n' (running as uid $(id -u))"
command -v unshare >/dev/null 2>&1 || skip "'unshare' not found (Debian: util-linux)"
command -v ip >/dev/null 2>&1 || skip "'ip' not found (Debian: iproute2)"
unshare -n true 2>/dev/null || skip "'unshare -n' is not permitted here (no CAP_SYS_ADMIN, e.g. an unprivileged container)"
# shellcheck disable=SC2016 # $0/$@ expand inside the namespace's shell
exec unshare -n sh -c '
    ip link set lo up || { echo "SKIPPED: cannot bring lo up in the namespace"; exit 77; }
    ip route add 224.0.0.0/4 dev lo || { echo "SKIPPED: cannot add the multicast route"; exit 77; }
    exec "$0" "$@"' "$@"
