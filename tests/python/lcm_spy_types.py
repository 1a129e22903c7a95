#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest lcm_spy_types: cdpr-lcm-spy gives lcm-spy the project's types (docs/realtime.md,
"lcm-spy").

  lcm_spy_types.py CDPR_LCM_SPY

`cdpr-lcm-spy --check` runs lcm-spy's own type lookup (lcm.spy.LCMTypeDatabase) on the class
path the wrapper gives lcm-spy, without a window. Checked here: it exits 0; it lists exactly the
message types of the Python package that lcm-gen generated from the same .lcm files (a second
generator), each with the same fingerprint and found by lcm-spy. The generated package is found
on PYTHONPATH (<build>/lcmtypes/python).
"""
import re
import subprocess
import sys

import cdpr

spy = sys.argv[1]
r = subprocess.run([spy, "--check"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
java = {}
for line in r.stdout.splitlines():
    m = re.match(r"^cdpr\.(\w+_t) ([0-9a-f]{16}) found by lcm-spy$", line)
    if m:
        java[m.group(1)] = m.group(2)
python = {n: getattr(cdpr, n)._get_packed_fingerprint().hex() for n in dir(cdpr)
          if n.endswith("_t") and hasattr(getattr(cdpr, n), "_get_packed_fingerprint")}
failures = 0
for what, ok in (("cdpr-lcm-spy --check exits 0 (exit %d)" % r.returncode, r.returncode == 0),
                 ("lcm-spy finds %d types: %s" % (len(java), ", ".join(sorted(java))),
                  len(java) == len(python) >= 5),
                 ("each with the fingerprint of the Python class lcm-gen made from the same file",
                  java == python)):
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1
if failures:
    print(r.stdout + r.stderr)
    print("python: %s" % python)
print("%d passed, %d failed" % (3 - failures, failures))
sys.exit(1 if failures else 0)
