#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A minimal closed-loop winch controller for cdpr-rt over LCM, lockstep-capable.

For every cabin_state_t k (with its cable_tensions_t k) it sends one winch_command_t whose
state_seq is k, so `cdpr-rt --lockstep` steps once per answer. The law is a length loop in
rate mode: each cable's measured unstretched length follows a reference, the lengths of the
first state plus `--lift` metres spread over `--ramp` seconds (a positive lift shortens every
cable, raising the cabin), u_j = k (L_ref_j - L_j) + dL_ref_j/dt, limited to --u-max.

  examples/python/controller.py [--lcm-url URL] [--prefix CDPR_] [--count N] [--timeout S]
                                [--first-timeout S]
                                [--gain K] [--lift M] [--ramp S] [--u-max U]

Sessions (docs/realtime.md, "Sessions"): the controller draws a random controller_session
once and puts it, with the plant_session of the state answered, in every command. It follows
one plant: the first it hears, then a new plant session only after the followed plant has been
silent for 0.5 s (a restarted plant: the controller starts over); states of another session
meanwhile are ignored and counted (two plants on one channel prefix).

Trust (docs/realtime.md, "The controller side"): the same rules as cdpr-tracker's. Each
(state, tensions) pair of the followed plant is checked before the law sees it: seq within
(last accepted, last accepted + 1000] (two refused pairs in a row that agree re-anchor the
window, backwards only while the anchor has no accepted successor), time never going back and
advancing by at most the periods the seq advanced (--period), every value finite, a unit
quaternion, |v| <= --speed-max, tensions in [0, --tension-max], lengths > 0 and changing by at
most --winch-u-max times the time elapsed. A refused pair changes nothing (counted; the first
refusal of each kind printed). After its first command, the controller counts whose command
the plant applied (cabin_state_t.controller_session): its own, none (held) or another
controller's, and warns at once when another controller holds the plant. At most 64 unpaired
messages are kept.

Exit status: 0 when at least one state (with --count: N states) was answered; 5 when the
plant applied another controller's commands in more than 1 % of the states after our first
command (not in control); 1 otherwise (also: 100 pairs in a row refused).
"""
import argparse
import math
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
                    help="stop after S seconds without a message once the first came (0: "
                         "never)")
    ap.add_argument("--first-timeout", type=float, default=60.0,
                    help="stop when no message came within S seconds of the start (default "
                         "60: a plant may take seconds to settle before it publishes)")
    ap.add_argument("--gain", type=float, default=2.0, help="length-loop gain k [1/s]")
    ap.add_argument("--lift", type=float, default=0.05, help="length change [m] (+: shorter)")
    ap.add_argument("--ramp", type=float, default=1.0, help="duration of the change [s]")
    ap.add_argument("--u-max", type=float, default=0.5, help="rate limit [m/s]")
    ap.add_argument("--period", type=float, default=0.0,
                    help="the plant's control period [s] for the time check (0: only "
                         "monotonic time is checked)")
    ap.add_argument("--speed-max", type=float, default=50.0,
                    help="largest plausible cabin speed [m/s] (default 50)")
    ap.add_argument("--tension-max", type=float, default=1e7,
                    help="largest plausible tension [N] (default 1e7: set the rope's EA)")
    ap.add_argument("--winch-u-max", type=float, default=4.0,
                    help="the winches' speed limit [m/s] (default 4, the winch default)")
    a = ap.parse_args()

    lc = lcm.LCM(a.lcm_url) if a.lcm_url else lcm.LCM()
    states = {}
    tens = {}
    ctl = {"answered": 0, "seq": 0, "l0": None, "t0": None, "last": -1, "cmd": b"",
           "session": secrets.randbits(63) or 1, "plant": 0, "heard": 0.0, "ignored": 0,
           "acc": None, "run": 0, "cand": None, "in_row": 0, "other_seen": 0,
           "last_other": None}
    refused = {"seq": 0, "time": 0, "value": 0}
    applied = {"ours": 0, "none": 0, "other": 0}
    window = 1000

    def follows(plant_session, is_state):
        """True for a message of the plant followed (or of a new one after a silence)."""
        now = time.monotonic()
        if plant_session == ctl["plant"]:
            if is_state:
                ctl["heard"] = now
            return True
        if ctl["plant"] == 0 and not is_state:
            return False  # tensions before the first state: no plant followed yet
        if is_state and (ctl["plant"] == 0 or now - ctl["heard"] > 0.5):
            if ctl["plant"] != 0:
                print("controller: plant restarted (session %d -> %d)" %
                      (ctl["plant"], plant_session), file=sys.stderr)
            ctl.update(plant=plant_session, heard=now, l0=None, t0=None, last=-1, cmd=b"",
                       acc=None, run=0, cand=None)
            states.clear()
            tens.clear()
            return True
        ctl["ignored"] += 1
        return False

    def reference(t):
        s = min(max((t - ctl["t0"]) / a.ramp, 0.0), 1.0) if a.ramp > 0 else 1.0
        rate = (-a.lift / a.ramp) if (a.ramp > 0 and 0.0 < s < 1.0) else 0.0
        return [l0 - a.lift * s for l0 in ctl["l0"]], rate

    def values_problem(s, m):
        """Why a pair's values are implausible, or None."""
        n = m.n_cables
        vals = (list(s.position_m) + list(s.orientation) + list(s.velocity_m_per_s) +
                list(s.angular_velocity_rad_per_s) + list(m.length_m[:n]) +
                list(m.tension_winch_N[:n]) + list(m.tension_cabin_N[:n]))
        if not all(math.isfinite(v) for v in vals):
            return "a value is not finite"
        if n < 1 or (ctl["l0"] is not None and n != len(ctl["l0"])):
            return "cable count %d" % n
        qn = sum(q * q for q in s.orientation)
        if abs(qn - 1.0) > 1e-6:
            return "orientation: |q|^2 = %.9g, not a unit quaternion" % qn
        v = math.sqrt(sum(x * x for x in s.velocity_m_per_s))
        if v > a.speed_max:
            return "cabin speed %.4g m/s above --speed-max %.4g" % (v, a.speed_max)
        for j in range(n):
            for t in (m.tension_winch_N[j], m.tension_cabin_N[j]):
                if not 0.0 <= t <= a.tension_max:
                    return "cable %d: tension %.4g N outside [0, %.4g] N" % (j + 1, t,
                                                                            a.tension_max)
            if not m.length_m[j] > 0.0:
                return "cable %d: length %.6g m" % (j + 1, m.length_m[j])
        return None

    def order_problem(s, m, ref):
        """Why a pair does not follow `ref` = (seq, utime_us, lengths), or None."""
        seq0, t0, l0 = ref
        dseq = s.seq - seq0
        if not 0 < dseq <= window:
            return "seq", "seq %d outside (%d, %d]" % (s.seq, seq0, seq0 + window)
        dt = s.utime_us - t0
        if dt < 0 or (a.period > 0 and dt > dseq * a.period * 1e6 + 1.0):
            return "time", "time %d us: %d us after %d periods" % (s.utime_us, dt, dseq)
        for j in range(m.n_cables):
            if abs(m.length_m[j] - l0[j]) > a.winch_u_max * dt * 1e-6 + 1e-9 * (1 + abs(l0[j])):
                return "value", "cable %d: length changed faster than --winch-u-max" % (j + 1)
        return None

    def accept(s, m):
        """Check a pair (the rules in the module's text); True to use it."""
        why = values_problem(s, m)
        kind = "value" if why else None
        if why is None and ctl["acc"] is not None:
            problem = order_problem(s, m, ctl["acc"])
            if problem is not None:
                kind, why = problem
                cand = ctl["cand"]
                backwards = s.seq < ctl["acc"][0]
                if (kind != "value" and cand is not None and order_problem(s, m, cand) is None
                        and (not backwards or ctl["run"] < 2)):
                    why = None  # two agreeing pairs: the window re-anchors on them
                    ctl["run"] = 0
                elif kind != "value":
                    ctl["cand"] = (s.seq, s.utime_us, list(m.length_m[:m.n_cables]))
        if why is not None:
            if refused[kind] == 0:
                print("controller: warning: a state was refused: %s" % why, file=sys.stderr)
            refused[kind] += 1
            ctl["in_row"] += 1
            return False
        ctl.update(acc=(s.seq, s.utime_us, list(m.length_m[:m.n_cables])), cand=None,
                   run=ctl["run"] + 1, in_row=0)
        # Another session's command applied again (same session and seq as before) is a
        # stopped controller's last command until the plant's watchdog holds: not a rival.
        applied_again = (s.controller_session, s.command_seq) == ctl["last_other"]
        if s.controller_session not in (0, ctl["session"]):
            ctl["last_other"] = (s.controller_session, s.command_seq)
        if ctl["answered"] > 0:
            if s.controller_session == ctl["session"]:
                applied["ours"] += 1
                if applied["ours"] == 1:
                    print("controller: in control: the plant applied our command in the step "
                          "to state %d" % s.seq, file=sys.stderr)
            elif s.controller_session == 0 or applied_again:
                applied["none"] += 1
            else:
                applied["other"] += 1
                if s.controller_session != ctl["other_seen"]:
                    ctl["other_seen"] = s.controller_session
                    print("controller: warning: the plant applied the commands of another "
                          "controller (session %d): not in control" % s.controller_session,
                          file=sys.stderr)
        return True

    def answer(k):
        s = states.pop(k)
        m = tens.pop(k)
        if k == ctl["last"] or not accept(s, m):
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
        values = [0.0] * n  # one per cable: the message sizes its array by n_cables
        for j in range(n):
            u = a.gain * (ref[j] - m.length_m[j]) + ref_rate
            values[j] = max(-a.u_max, min(a.u_max, u))
        cmd.value = values
        ctl["cmd"] = cmd.encode()
        lc.publish(a.prefix + "WINCH_COMMAND", ctl["cmd"])
        ctl["answered"] += 1
        ctl["last"] = k

    def pair_up(mine, msg, other):
        """Keep `msg` (the last 64 by seq) and answer once its partner is in `other`."""
        mine[msg.seq] = msg
        while len(mine) > 64:
            del mine[min(mine)]
        if msg.seq in other:
            answer(msg.seq)

    def on_state(channel, data):
        s = cabin_state_t.decode(data)
        if not follows(s.plant_session, True):
            return
        if s.seq == ctl["last"]:
            # A state sent again (lockstep: our answer may have been lost): answer again; the
            # plant ignores the copy as replayed if it had it.
            lc.publish(a.prefix + "WINCH_COMMAND", ctl["cmd"])
            return
        pair_up(states, s, tens)

    def on_tensions(channel, data):
        m = cable_tensions_t.decode(data)
        if not follows(m.plant_session, False):
            return
        pair_up(tens, m, states)

    lc.subscribe(a.prefix + "CABIN_STATE", on_state)
    lc.subscribe(a.prefix + "CABLE_TENSIONS", on_tensions)
    timeout_ms = int(a.timeout * 1000) if a.timeout > 0 else 1000
    print("controller: session %d, waiting for %sCABIN_STATE" % (ctl["session"], a.prefix),
          file=sys.stderr, flush=True)
    heard = {"any": False}

    def note(channel, data):
        heard["any"] = True

    lc.subscribe(a.prefix + "CABIN_STATE", note)
    t_start = time.monotonic()
    try:
        while a.count <= 0 or ctl["answered"] < a.count:
            got = lc.handle_timeout(timeout_ms)
            if not heard["any"]:
                if time.monotonic() - t_start > a.first_timeout:
                    print("controller: no state within %g s: stopping" % a.first_timeout,
                          file=sys.stderr)
                    break
                continue
            if got == 0 and a.timeout > 0:
                break
            if ctl["in_row"] >= 100:
                print("controller: 100 states in a row refused: stopping", file=sys.stderr)
                return 1
    except KeyboardInterrupt:
        pass
    print("controller: answered %d states (last state seq %d) of a %s-cable plant" %
          (ctl["answered"], ctl["last"], len(ctl["l0"]) if ctl["l0"] is not None else "?"))
    if ctl["ignored"]:
        print("controller: warning: %d messages of another plant session ignored" %
              ctl["ignored"], file=sys.stderr)
    if any(refused.values()):
        print("controller: refused states: %d outside the sequence window, %d with a bad "
              "time, %d implausible" % (refused["seq"], refused["time"], refused["value"]),
              file=sys.stderr)
    counted = sum(applied.values())
    if applied["other"] or applied["none"]:
        print("controller: after its first command the plant applied its commands in %d "
              "periods, none in %d, another controller's in %d" %
              (applied["ours"], applied["none"], applied["other"]), file=sys.stderr)
    if counted and applied["other"] > 0.01 * counted:
        print("controller: not in control: another controller held the plant", file=sys.stderr)
        return 5
    want = a.count if a.count > 0 else 1
    return 0 if ctl["answered"] >= want else 1


if __name__ == "__main__":
    sys.exit(main())
