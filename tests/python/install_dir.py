# SPDX-License-Identifier: BSD-3-Clause
"""Is <prefix>/<CDPR_INSTALL_PYTHONDIR> on this Python's own path? (tests/python/CMakeLists.txt)

usage: install_dir.py PREFIX RELATIVE_DIR
Exit 0: it is, so the installed package `cdpr` imports without PYTHONPATH; 1: it is not;
77 (skipped): PREFIX is neither /usr nor /usr/local, whose directories Debian's python3 searches.
"""
import os
import sys


def main():
    prefix, rel = sys.argv[1], sys.argv[2]
    if os.path.normpath(prefix) not in ("/usr", "/usr/local"):
        print("SKIPPED: prefix %s: its packages go on PYTHONPATH" % prefix)
        return 77
    full = os.path.normpath(os.path.join(prefix, rel))
    if full in sys.path:
        print("%s is on %s's path" % (full, sys.executable))
        return 0
    print("FAIL: %s is not on %s's path %s" % (full, sys.executable, sys.path))
    return 1


if __name__ == "__main__":
    sys.exit(main())
