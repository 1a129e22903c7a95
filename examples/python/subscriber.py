#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Print the cabin state and the cable tensions that cdpr-rt publishes, live.

Uses LCM's own Python binding (the `lcm` module, built from Debian's lcm source package by
scripts/setup.sh) and the message classes lcm-gen generates at build time (the `cdpr`
package). docs/realtime.md, "Python", says where both are and how to set PYTHONPATH.

  examples/python/subscriber.py [--lcm-url URL] [--prefix CDPR_] [--count N] [--timeout S]
                                [--every N]

Each state is printed with the tensions of the same period (the plant sends them just after
it; "(no tensions)" when they never came). --count N stops once N states and N tension
messages came; --every N prints every Nth state.

Exit status: 0 when at least one state (with --count: N states) was decoded, 1 otherwise.
"""
import argparse
import sys

import _cdpr_path  # noqa: F401  (sys.path fallback for a source tree)
import lcm
from cdpr import cabin_state_t, cable_tensions_t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lcm-url", default=None, help="LCM provider (default: liblcm's)")
    ap.add_argument("--prefix", default="CDPR_", help="channel prefix (default CDPR_)")
    ap.add_argument("--count", type=int, default=0, help="stop after N states (0: never)")
    ap.add_argument("--timeout", type=float, default=0.0,
                    help="stop after S seconds without a message (0: never)")
    ap.add_argument("--every", type=int, default=1, help="print every Nth state")
    a = ap.parse_args()

    lc = lcm.LCM(a.lcm_url) if a.lcm_url else lcm.LCM()
    n = {"states": 0, "tensions": 0, "shown": 0}
    # The plant publishes a period's state, then its tensions (same seq): a state waits here
    # for its tensions; tensions that come first (another transport's order) wait too.
    states = {}
    tensions = {}

    def show(s, t):
        if n["shown"] % max(a.every, 1) == 0:
            tt = (" T=[" + " ".join("%7.1f" % x for x in t.tension_cabin_N[:t.n_cables]) + "] N"
                  if t is not None else " (no tensions)")
            print("t=%8.3f s seq=%6d p=(%8.4f %8.4f %8.4f) m flags=%d%s"
                  % (s.utime_us * 1e-6, s.seq, s.position_m[0], s.position_m[1],
                     s.position_m[2], s.flags, tt), flush=True)
        n["shown"] += 1

    def on_tensions(channel, data):
        m = cable_tensions_t.decode(data)
        n["tensions"] += 1
        s = states.pop(m.seq, None)
        if s is not None:
            show(s, m)
            return
        tensions[m.seq] = m
        for old in [k for k in tensions if k < m.seq - 100]:
            del tensions[old]

    def on_state(channel, data):
        s = cabin_state_t.decode(data)
        n["states"] += 1
        # An earlier state whose tensions never came: shown without them, in order.
        for k in sorted(k for k in states if k < s.seq):
            show(states.pop(k), None)
        t = tensions.pop(s.seq, None)
        if t is not None:
            show(s, t)
        else:
            states[s.seq] = s

    lc.subscribe(a.prefix + "CABLE_TENSIONS", on_tensions)
    lc.subscribe(a.prefix + "CABIN_STATE", on_state)
    timeout_ms = int(a.timeout * 1000) if a.timeout > 0 else 1000
    try:
        while a.count <= 0 or min(n["states"], n["tensions"]) < a.count:
            if lc.handle_timeout(timeout_ms) == 0 and a.timeout > 0:
                break
    except KeyboardInterrupt:
        pass
    for k in sorted(states):
        show(states.pop(k), None)
    print("subscriber: %d states and %d tension messages decoded" % (n["states"], n["tensions"]))
    want = a.count if a.count > 0 else 1
    return 0 if n["states"] >= want else 1


if __name__ == "__main__":
    sys.exit(main())
