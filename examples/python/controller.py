#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A minimal closed-loop winch controller for cdpr-rt over LCM, lockstep-capable.

For every cabin_state_t k (with its cable_tensions_t k) it sends one winch_command_t whose
state_seq is k, so `cdpr-rt --lockstep` steps once per answer. The law is a length loop in
rate mode: each cable's measured unstretched length follows a reference, the lengths of the
first state plus `--lift` metres spread over `--ramp` seconds (a positive lift shortens every
cable, raising the cabin), u_j = k (L_ref_j - L_j) + dL_ref_j/dt, limited to --u-max.

  examples/python/controller.py [--lcm-url URL] [--prefix CDPR_] [--count N] [--timeout S]
                                [--gain K] [--lift M] [--ramp S] [--u-max U]

Sessions (docs/realtime.md, "Sessions"): the controller draws a random controller_session
once and puts it, with the plant_session of the state answered, in every command. It follows
one plant: the first it hears, then a new plant session only after the followed plant has been
silent for 0.5 s (a restarted plant: the controller starts over); states of another session
meanwhile are ignored and counted (two plants on one channel prefix).

Exit status: 0 when at least one state (with --count: N states) was answered, 1 otherwise.
"""
import argparse
import secrets
import sys
import time

import _cdpr_path  # noqa: F401  (sys.path fallback for a source tree)
import lcm
from cdpr import cabin_state_t, cable_tensions_t, winch_command_t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lcm-url", default=None, help="LCM provider (default: liblcm's)")
    ap.add_argument("--prefix", default="CDPR_", help="channel prefix (default CDPR_)")
    ap.add_argument("--count", type=int, default=0, help="stop after answering N states")
    ap.add_argument("--timeout", type=float, default=0.0,
                    help="stop after S seconds without a message (0: never)")
    ap.add_argument("--gain", type=float, default=2.0, help="length-loop gain k [1/s]")
    ap.add_argument("--lift", type=float, default=0.05, help="length change [m] (+: shorter)")
    ap.add_argument("--ramp", type=float, default=1.0, help="duration of the change [s]")
    ap.add_argument("--u-max", type=float, default=0.5, help="rate limit [m/s]")
    a = ap.parse_args()

    lc = lcm.LCM(a.lcm_url) if a.lcm_url else lcm.LCM()
    states = {}
    tens = {}
    ctl = {"answered": 0, "seq": 0, "l0": None, "t0": None, "last": -1, "cmd": b"",
           "session": secrets.randbits(63) or 1, "plant": 0, "heard": 0.0, "ignored": 0}

    def follows(plant_session, is_state):
        """True for a message of the plant followed (or of a new one after a silence)."""
        now = time.monotonic()
        if plant_session == ctl["plant"]:
            if is_state:
                ctl["heard"] = now
            return True
        if is_state and (ctl["plant"] == 0 or now - ctl["heard"] > 0.5):
            if ctl["plant"] != 0:
                print("controller: plant restarted (session %d -> %d)" %
                      (ctl["plant"], plant_session), file=sys.stderr)
            ctl.update(plant=plant_session, heard=now, l0=None, t0=None, last=-1, cmd=b"")
            states.clear()
            tens.clear()
            return True
        ctl["ignored"] += 1
        return False

    def reference(t):
        s = min(max((t - ctl["t0"]) / a.ramp, 0.0), 1.0) if a.ramp > 0 else 1.0
        rate = (-a.lift / a.ramp) if (a.ramp > 0 and 0.0 < s < 1.0) else 0.0
        return [l0 - a.lift * s for l0 in ctl["l0"]], rate

    def answer(k):
        s = states.pop(k)
        m = tens.pop(k)
        if k <= ctl["last"]:
            return
        t = s.utime_us * 1e-6
        n = m.n_cables
        if ctl["l0"] is None:
            ctl["l0"] = list(m.length_m[:n])
            ctl["t0"] = t
        ref, ref_rate = reference(t)
        cmd = winch_command_t()
        cmd.utime_us = s.utime_us
        ctl["seq"] += 1
        cmd.seq = ctl["seq"]
        cmd.state_seq = s.seq
        cmd.controller_session = ctl["session"]
        cmd.plant_session = s.plant_session
        cmd.mode = winch_command_t.MODE_RATE
        cmd.n_cables = n
        values = [0.0] * winch_command_t.MAX_CABLES
        for j in range(n):
            u = a.gain * (ref[j] - m.length_m[j]) + ref_rate
            values[j] = max(-a.u_max, min(a.u_max, u))
        cmd.value = values
        ctl["cmd"] = cmd.encode()
        lc.publish(a.prefix + "WINCH_COMMAND", ctl["cmd"])
        ctl["answered"] += 1
        ctl["last"] = k

    def on_state(channel, data):
        s = cabin_state_t.decode(data)
        if not follows(s.plant_session, True):
            return
        if s.seq == ctl["last"]:
            # A state sent again (lockstep: our answer may have been lost): answer again; the
            # plant ignores the copy as replayed if it had it.
            lc.publish(a.prefix + "WINCH_COMMAND", ctl["cmd"])
            return
        states[s.seq] = s
        if s.seq in tens:
            answer(s.seq)

    def on_tensions(channel, data):
        m = cable_tensions_t.decode(data)
        if not follows(m.plant_session, False):
            return
        tens[m.seq] = m
        if m.seq in states:
            answer(m.seq)

    lc.subscribe(a.prefix + "CABIN_STATE", on_state)
    lc.subscribe(a.prefix + "CABLE_TENSIONS", on_tensions)
    timeout_ms = int(a.timeout * 1000) if a.timeout > 0 else 1000
    try:
        while a.count <= 0 or ctl["answered"] < a.count:
            if lc.handle_timeout(timeout_ms) == 0 and a.timeout > 0:
                break
    except KeyboardInterrupt:
        pass
    print("controller: answered %d states (last state seq %d)" % (ctl["answered"], ctl["last"]))
    if ctl["ignored"]:
        print("controller: warning: %d messages of another plant session ignored" %
              ctl["ignored"], file=sys.stderr)
    want = a.count if a.count > 0 else 1
    return 0 if ctl["answered"] >= want else 1


if __name__ == "__main__":
    sys.exit(main())
