#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Inject forged winch commands next to a live controller (the fault suite's seq poisoning).

Waits for the first winch_command_t another controller publishes, then publishes, once each:
  - a copy with seq = 2**63 - 11 (a poisoned sequence number of the live session);
  - a copy with a new controller session (a second controller while the first is live);
  - a copy answering another plant session.
Fields the generated types of the build do not have (an older protocol) are left out.
With --flood S it instead publishes, for S seconds and as fast as it can, a copy of that
command (refused as replayed/stale) and a 12-byte garbage message, in turn.
Usage: inject.py LCM_URL [--flood S] [PREFIX]
"""
import sys
import time

import lcm
from cdpr import winch_command_t


def main():
    args = sys.argv[1:]
    url = args.pop(0)
    flood_s = 0.0
    if args and args[0] == "--flood":
        flood_s = float(args[1])
        args = args[2:]
    prefix = args[0] if args else "CDPR_"
    lc = lcm.LCM(url)
    got = []
    lc.subscribe(prefix + "WINCH_COMMAND", lambda ch, data: got.append(data))
    t0 = time.monotonic()
    while not got and time.monotonic() - t0 < 30:
        lc.handle_timeout(100)
    if not got:
        print("inject: no command seen", file=sys.stderr)
        return 1
    ch = prefix + "WINCH_COMMAND"
    if flood_s > 0:
        junk = bytes(range(1, 13))
        n = 0
        t_end = time.monotonic() + flood_s
        while time.monotonic() < t_end:
            for _ in range(100):
                lc.publish(ch, got[0])
                lc.publish(ch, junk)
            n += 200
        print("inject: %d messages in %.1f s" % (n, flood_s), file=sys.stderr)
        return 0
    m = winch_command_t.decode(got[0])
    m.seq = 2**63 - 11
    lc.publish(ch, m.encode())
    if hasattr(m, "controller_session"):
        m = winch_command_t.decode(got[-1])
        m.controller_session = (m.controller_session ^ 0x5A5A5A5A) or 1
        m.seq += 1
        lc.publish(ch, m.encode())
        m = winch_command_t.decode(got[-1])
        m.plant_session = (m.plant_session ^ 0x33333333) or 1
        m.seq += 1
        lc.publish(ch, m.encode())
    print("inject: forged commands published", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
