#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Inject forged winch commands next to a live controller (the fault suite's seq poisoning).

Waits for the first winch_command_t another controller publishes, then publishes, once each:
  - a copy with seq = 2**63 - 11 (a poisoned sequence number of the live session);
  - a copy with a new controller session (a second controller while the first is live);
  - a copy answering another plant session.
Fields the generated types of the build do not have (an older protocol) are left out.
Usage: inject.py LCM_URL [PREFIX]
"""
import sys
import time

import lcm
from cdpr import winch_command_t


def main():
    url = sys.argv[1]
    prefix = sys.argv[2] if len(sys.argv) > 2 else "CDPR_"
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
