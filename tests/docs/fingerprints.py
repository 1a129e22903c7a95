# SPDX-License-Identifier: BSD-3-Clause
"""doc_fingerprints: the fingerprint and size table of docs/realtime.md ("Sessions") must match
the message types of this build (lcm-gen's Python classes): each type's fingerprint and its
encoded size with six and with eight cables (the shape with MAX_NODES nodes per cable, its
largest). Fails on a changed .lcm file whose table was not updated, so peers can trust the table.
Usage: fingerprints.py DOC"""
import re
import sys

import cdpr

# Per-cable arrays of each type (sized by n_cables on the wire), and the shape's node arrays.
PER_CABLE = {
    "cable_tensions_t": ("tension_cabin_N", "tension_winch_N", "length_m", "payout_m_per_s",
                         "n_segments"),
    "winch_command_t": ("value",),
    "cable_shape_t": ("n_segments", "n_nodes"),
}


def encoded_size(name, n):
    """Bytes of a `name` message of n cables (every array full)."""
    m = getattr(cdpr, name)()
    if name in PER_CABLE:
        m.n_cables = n
        for field in PER_CABLE[name]:
            setattr(m, field, [0] * n)
    if name == "cable_shape_t":
        m.n_points = n * cdpr.cable_shape_t.MAX_NODES
        m.node_x_m = m.node_y_m = m.node_z_m = [0.0] * m.n_points
    return len(m.encode())


def main():
    doc = open(sys.argv[1], encoding="utf-8").read()
    rows = re.findall(r"^\| `(\w+_t)` \| `([0-9a-f]{16})` \| (?:≤ )?(\d+) \| (?:≤ )?(\d+) \|$",
                      doc, re.M)
    if len(rows) != 5:
        print("FAIL: expected 5 rows in the fingerprint table, found %d" % len(rows))
        return 1
    bad = 0
    for name, fp, size6, size8 in rows:
        got_fp = getattr(cdpr, name)._get_packed_fingerprint().hex()
        got = (encoded_size(name, 6), encoded_size(name, 8))
        if got_fp != fp or got != (int(size6), int(size8)):
            print("FAIL: %s: documented %s, %s/%s bytes; built %s, %d/%d bytes" %
                  (name, fp, size6, size8, got_fp, got[0], got[1]))
            bad += 1
    if bad == 0:
        print("PASS: %d fingerprints and sizes (6 and 8 cables) as documented" % len(rows))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
