#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Live view of the cabin and the sagging cables, from LCM or from an lcm-logger log.

Draws every cable's nodes (cable_shape_t on <prefix>CABLE_SHAPE, which cdpr-rt publishes at a
few Hz), the cabin as the polygon of the cable attachments with its body origin
(cabin_state_t on <prefix>CABIN_STATE), and the towers under the exit points. Matplotlib of
Debian (python3-matplotlib) and LCM's own Python binding (docs/realtime.md, "Python").

  examples/python/viewer.py [--lcm-url URL] [--prefix CDPR_]      live, until the window closes
  examples/python/viewer.py --log FILE [--speed X]                replay a log
  ... --png OUT [--frame N]                                       headless (Agg): render one
                                                                  frame to OUT and exit

With --png the live mode renders the first shape that arrives (--timeout S: give up after S
seconds, exit status 1), the log mode frame N (default: the last). Exit status 0 when the PNG
was written (or the window was closed).
"""
import argparse
import sys

import _cdpr_path  # noqa: F401  (sys.path fallback for a source tree)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("--lcm-url", default=None, help="LCM provider (default: liblcm's)")
ap.add_argument("--prefix", default="CDPR_", help="channel prefix (default CDPR_)")
ap.add_argument("--log", default=None, help="lcm-logger log to replay instead of LCM")
ap.add_argument("--speed", type=float, default=1.0, help="log replay speed factor")
ap.add_argument("--png", default=None, help="render one frame to this PNG (headless) and exit")
ap.add_argument("--frame", type=int, default=-1, help="--log --png: shape frame index (-1: last)")
ap.add_argument("--timeout", type=float, default=10.0, help="live --png: seconds to wait")
args = ap.parse_args()

import matplotlib  # noqa: E402

if args.png:
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import lcm  # noqa: E402
from cdpr import cabin_state_t, cable_shape_t  # noqa: E402


class View:
    """One 3D axes; draw(shape, state) redraws everything."""

    def __init__(self):
        self.fig = plt.figure(figsize=(7, 6))
        self.ax = self.fig.add_subplot(projection="3d")
        self.limits = None

    def draw(self, shape, state):
        ax = self.ax
        ax.cla()
        n = shape.n_cables
        ends = []
        xs_all, ys_all, zs_all = [], [], []
        first = 0  # the cables' nodes come one cable after the other
        for j in range(n):
            k = shape.n_nodes[j]
            xs = list(shape.node_x_m[first:first + k])
            ys = list(shape.node_y_m[first:first + k])
            zs = list(shape.node_z_m[first:first + k])
            nodes = list(zip(xs, ys, zs))
            first += k
            ax.plot(xs, ys, zs, "-", color="C%d" % j, lw=1.2, label="cable %d" % (j + 1))
            ax.plot([xs[-1], xs[-1]], [ys[-1], ys[-1]], [0.0, zs[-1]], "-", color="0.6", lw=3)
            ends.append(nodes[0])
            xs_all += xs
            ys_all += ys
            zs_all += zs
        # The cabin: its attachment points (node 0 of every cable), closed.
        ring = ends + ends[:1]
        ax.plot([p[0] for p in ring], [p[1] for p in ring], [p[2] for p in ring], "k-", lw=2)
        title = "t = %.2f s (state %d)" % (shape.utime_us * 1e-6, shape.seq)
        if state is not None:
            p = state.position_m
            ax.plot([p[0]], [p[1]], [p[2]], "ko", ms=5)
            title += ", cabin at (%.2f, %.2f, %.2f) m" % (p[0], p[1], p[2])
        if self.limits is None:
            span = max(max(xs_all) - min(xs_all), max(ys_all) - min(ys_all), max(zs_all)) / 2
            cx = (max(xs_all) + min(xs_all)) / 2
            cy = (max(ys_all) + min(ys_all)) / 2
            self.limits = ((cx - span, cx + span), (cy - span, cy + span), (0.0, 2 * span))
        ax.set_xlim(*self.limits[0])
        ax.set_ylim(*self.limits[1])
        ax.set_zlim(*self.limits[2])
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.set_title(title, fontsize=9)
        ax.legend(loc="upper left", fontsize=7)

    def save(self, path):
        self.fig.savefig(path, dpi=80)
        print("viewer: wrote %s" % path)


def read_log(path, prefix):
    """(shape, latest state at or before it) pairs of a log, in order."""
    frames = []
    state = None
    for ev in lcm.EventLog(path, "r"):
        if ev.channel == prefix + "CABIN_STATE":
            state = cabin_state_t.decode(ev.data)
        elif ev.channel == prefix + "CABLE_SHAPE":
            frames.append((ev.timestamp, cable_shape_t.decode(ev.data), state))
    return frames


def run_log():
    frames = read_log(args.log, args.prefix)
    if not frames:
        print("viewer: no %sCABLE_SHAPE message in %s" % (args.prefix, args.log))
        return 1
    view = View()
    if args.png:
        _, shape, state = frames[args.frame]
        view.draw(shape, state)
        view.save(args.png)
        return 0
    plt.ion()
    for i, (stamp, shape, state) in enumerate(frames):
        if not plt.fignum_exists(view.fig.number):
            break
        view.draw(shape, state)
        dt = (frames[i + 1][0] - stamp) * 1e-6 / args.speed if i + 1 < len(frames) else 0.5
        plt.pause(max(dt, 0.01))
    plt.ioff()
    plt.show()
    return 0


def run_live():
    lc = lcm.LCM(args.lcm_url) if args.lcm_url else lcm.LCM()
    latest = {"shape": None, "state": None, "new": False}

    def on_shape(channel, data):
        latest["shape"] = cable_shape_t.decode(data)
        latest["new"] = True

    def on_state(channel, data):
        latest["state"] = cabin_state_t.decode(data)

    lc.subscribe(args.prefix + "CABLE_SHAPE", on_shape)
    lc.subscribe(args.prefix + "CABIN_STATE", on_state)
    view = View()
    if args.png:
        waited = 0.0
        while latest["shape"] is None and waited < args.timeout:
            lc.handle_timeout(100)
            waited += 0.1
        if latest["shape"] is None:
            print("viewer: no %sCABLE_SHAPE within %g s" % (args.prefix, args.timeout))
            return 1
        view.draw(latest["shape"], latest["state"])
        view.save(args.png)
        return 0
    plt.ion()
    plt.show()
    while plt.fignum_exists(view.fig.number):
        lc.handle_timeout(20)
        if latest["new"]:
            latest["new"] = False
            view.draw(latest["shape"], latest["state"])
        plt.pause(0.05)
    return 0


if __name__ == "__main__":
    sys.exit(run_log() if args.log else run_live())
