# SPDX-License-Identifier: BSD-3-Clause
"""Find the lcm module and the generated cdpr message types (docs/realtime.md, "Python").

Both are found through PYTHONPATH when set. As a fallback for running the examples from a
source tree, this adds the places scripts/setup.sh and the build put them:
  $CDPR_LCM_PYTHON, else ~/.cache/cdpr/lcm-python     (the lcm module, built at set-up)
  $CDPR_LCMTYPES_PYTHON, else the first of build/release/lcmtypes/python (the README's
  build) and build/debug/lcmtypes/python that exists   (the cdpr package, lcm-gen -p)
  the first of build/release/python and build/debug/python holding cdprlib (the library's
  own package, docs/python.md)
An installed package (cmake --install: on Debian python3's path) is found first.
"""
import os
import sys


def _add(path):
    if path and os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)


_here = os.path.dirname(os.path.abspath(__file__))
_add(os.environ.get("CDPR_LCM_PYTHON") or os.path.expanduser("~/.cache/cdpr/lcm-python"))
_types = os.environ.get("CDPR_LCMTYPES_PYTHON")
if not _types:
    for _tree in ("release", "debug"):
        _types = os.path.join(_here, "..", "..", "build", _tree, "lcmtypes", "python")
        if os.path.isdir(os.path.join(_types, "cdpr")):
            break
_add(_types)
for _tree in ("release", "debug"):
    _lib = os.path.join(_here, "..", "..", "build", _tree, "python")
    if os.path.isdir(os.path.join(_lib, "cdprlib")):
        _add(_lib)
        break
