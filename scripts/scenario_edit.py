#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Edit the keys of a scenario file with a YAML library (for the study scripts).

    from scenario_edit import edit
    text = edit(text, [("controller.kd_s", "0.1"), ("robot.rope.damping_Ns", None)], base_dir)

Each edit is a dotted key path (mapping keys joined by '.', `[i]` for a list entry, as in
cdpr-sweep's sweep files: docs/sweeps.md) and a value written as YAML (`0.1`, `[0, 0, 0]`,
`true`), or None to delete the key (an error when it is not there). Missing mappings along a
path are made; the scenario's own check refuses a key that does not exist. ruamel.yaml's round
trip keeps the file's comments and layout. With `base_dir` (the folder of the file the text came
from), a relative `robot.file` is made absolute, so that the edited copy can be written anywhere.
This replaces the line-based editing of the former scripts/gain_sweep.py, which corrupted
flow-style YAML and broke relative robot-file paths.

As a command: scenario_edit.py SCENARIO KEY=VALUE... [-KEY...] prints the edited scenario.
"""
import io
import os
import re
import sys

from ruamel.yaml import YAML


class EditError(Exception):
    """A key path that cannot be edited (a list index out of range, a key to delete missing)."""


def _parts(key):
    out = []
    for part in key.split("."):
        m = re.match(r"^([A-Za-z_][A-Za-z0-9_]*)((\[[0-9]+\])*)$", part)
        if not m:
            raise EditError("%s: '%s' is not a key name (letters, digits, _; [i] for a list "
                            "entry)" % (key, part))
        out.append(m.group(1))
        out.extend(int(i) for i in re.findall(r"\[([0-9]+)\]", m.group(2)))
    return out


def _value(text):
    v = YAML(typ="safe").load(text)
    return v


def set_in(doc, key, value, delete=False):
    """doc[key] = value (or delete it) for a dotted key path."""
    node = doc
    parts = _parts(key)
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(p, int):
            if not isinstance(node, list) or p >= len(node):
                raise EditError("%s: no list entry [%d] there" % (key, p))
        elif not isinstance(node, dict):
            raise EditError("%s: '%s' is not inside a mapping" % (key, p))
        if last:
            if delete:
                if isinstance(p, int) or p not in node:
                    raise EditError("%s: not in the scenario, cannot delete it" % key)
                del node[p]
            else:
                node[p] = value
            return
        if not isinstance(p, int) and (p not in node or node[p] is None):
            if delete:
                raise EditError("%s: not in the scenario, cannot delete it" % key)
            node[p] = {}
        node = node[p]


def edit(text, edits, base_dir=None):
    """The scenario text with `edits` [(key, YAML value text or None to delete)] applied."""
    y = YAML()  # round trip, in the shipped files' layout
    y.width = 4096
    y.preserve_quotes = True
    y.indent(mapping=2, sequence=4, offset=2)
    doc = y.load(text)
    for key, value in edits:
        if value is None:
            set_in(doc, key, None, delete=True)
        else:
            set_in(doc, key, _value(value))
    robot = doc.get("robot") if isinstance(doc, dict) else None
    if base_dir is not None and isinstance(robot, dict) and isinstance(robot.get("file"), str):
        if not os.path.isabs(robot["file"]):
            robot["file"] = os.path.normpath(os.path.join(os.path.abspath(base_dir), robot["file"]))
    buf = io.StringIO()
    y.dump(doc, buf)
    return buf.getvalue()


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        sys.stdout.write(__doc__)
        return 0 if argv else 2
    path = argv[0]
    edits = []
    for a in argv[1:]:
        if a.startswith("-"):
            edits.append((a[1:], None))
        elif "=" in a:
            k, v = a.split("=", 1)
            edits.append((k, v))
        else:
            sys.stderr.write("scenario_edit: '%s': KEY=VALUE or -KEY\n" % a)
            return 2
    try:
        with open(path) as f:
            sys.stdout.write(edit(f.read(), edits, os.path.dirname(path)))
    except (OSError, EditError) as e:
        sys.stderr.write("scenario_edit: %s\n" % e)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
