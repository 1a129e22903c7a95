#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Forge plant states next to a live plant (the fault suite's hostile plant side).

Follows the live plant's CABIN_STATE and CABLE_TENSIONS; at every 40th state k (for --rounds
rounds) it publishes copies of that period's pair with the live plant session:
  - seq = k + 2**40 (a poisoned sequence number);
  - seq = k + 3 with a winch-end tension of 1e300 N on cable 3;
  - seq = k + 4 with the time of the end of an 8 s run (a forged end time).
Usage: inject_state.py LCM_URL [--rounds N] [PREFIX]
"""
import sys
import time

import lcm
from cdpr import cabin_state_t, cable_tensions_t


def main():
    args = sys.argv[1:]
    url = args.pop(0)
    rounds = 3
    if args and args[0] == "--rounds":
        rounds = int(args[1])
        args = args[2:]
    prefix = args[0] if args else "CDPR_"
    lc = lcm.LCM(url)
    tens = {}
    done = {"rounds": 0, "states": 0}

    def publish(s, m):
        m.seq = s.seq
        m.utime_us = s.utime_us
        lc.publish(prefix + "CABIN_STATE", s.encode())
        lc.publish(prefix + "CABLE_TENSIONS", m.encode())

    def on_tensions(channel, data):
        m = cable_tensions_t.decode(data)
        tens[m.seq] = data
        while len(tens) > 8:
            del tens[min(tens)]

    def on_state(channel, data):
        done["states"] += 1
        s = cabin_state_t.decode(data)
        if s.seq < 20 or s.seq % 40 != 0 or done["rounds"] >= rounds or s.seq - 1 not in tens:
            return
        base_t = cable_tensions_t.decode(tens[s.seq - 1])
        f = cabin_state_t.decode(data)
        f.seq = s.seq + 2**40
        publish(f, cable_tensions_t.decode(tens[s.seq - 1]))
        f = cabin_state_t.decode(data)
        f.seq = s.seq + 3
        m = cable_tensions_t.decode(tens[s.seq - 1])
        values = list(m.tension_winch_N)
        values[2] = 1e300
        m.tension_winch_N = values
        publish(f, m)
        f = cabin_state_t.decode(data)
        f.seq = s.seq + 4
        f.utime_us = 8000000
        publish(f, base_t)
        done["rounds"] += 1

    lc.subscribe(prefix + "CABIN_STATE", on_state)
    lc.subscribe(prefix + "CABLE_TENSIONS", on_tensions)
    t0 = time.monotonic()
    while done["rounds"] < rounds and time.monotonic() - t0 < 60:
        lc.handle_timeout(100)
    if done["rounds"] < rounds:
        print("inject_state: %d of %d rounds (%d states seen)" %
              (done["rounds"], rounds, done["states"]), file=sys.stderr)
        return 1
    print("inject_state: %d rounds of forged states published" % rounds, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
