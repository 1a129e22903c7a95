# SPDX-License-Identifier: BSD-3-Clause
"""doc_fingerprints: the fingerprint and size table of docs/realtime.md ("Sessions") must match
the message types of this build (lcm-gen's Python classes). Fails on a changed .lcm file whose
table was not updated, so peers can trust the table.
Usage: fingerprints.py DOC"""
import re
import sys

import cdpr


def main():
    doc = open(sys.argv[1], encoding="utf-8").read()
    rows = re.findall(r"^\| `(\w+_t)` \| `([0-9a-f]{16})` \| (\d+) \|$", doc, re.M)
    if len(rows) != 5:
        print("FAIL: expected 5 rows in the fingerprint table, found %d" % len(rows))
        return 1
    bad = 0
    for name, fp, size in rows:
        t = getattr(cdpr, name)
        got_fp = t._get_packed_fingerprint().hex()
        got_size = len(t().encode())
        if got_fp != fp or got_size != int(size):
            print("FAIL: %s: documented %s, %s bytes; built %s, %d bytes" %
                  (name, fp, size, got_fp, got_size))
            bad += 1
    if bad == 0:
        print("PASS: %d fingerprints and sizes as documented" % len(rows))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
