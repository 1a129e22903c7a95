#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Licence identifiers (LICENSE: BSD-3-Clause). Lists the tracked source files -- *.c, *.h,
# *.cmake, CMakeLists.txt, *.sh, *.py, *.gp, *.lcm, *.yaml -- whose first three lines lack
# "SPDX-License-Identifier: BSD-3-Clause"; exit status 1 if there is any (scripts/test.sh
# stage `spdx`).
#
#   scripts/spdx.sh [--fix] [path...]
#
# path...: only files under these paths (default: the whole repository). --fix inserts the
# identifier as the first line, after a shebang line if there is one, in the file type's
# comment syntax: /* ... */ for C, // ... for LCM, # ... for the rest; then lists what is
# still missing (nothing).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

id='SPDX-License-Identifier: BSD-3-Clause'
fix=0
if [[ ${1:-} == --fix ]]; then
    fix=1
    shift
fi
if [[ ${1:-} == -* ]]; then
    echo "usage: $0 [--fix] [path...]" >&2
    exit 2
fi

# comment_for <file>: the identifier line in the file's comment syntax.
comment_for() {
    case $1 in
    *.c | *.h) printf '/* %s */\n' "$id" ;;
    *.lcm) printf '// %s\n' "$id" ;;
    *) printf '# %s\n' "$id" ;;
    esac
}

# insert <file>: the identifier as line 1, or line 2 after a shebang.
insert() {
    local f=$1 tmp
    tmp=$(mktemp)
    if head -n 1 "$f" | grep '^#!' >/dev/null; then
        { head -n 1 "$f"; comment_for "$f"; tail -n +2 "$f"; } >"$tmp"
    else
        { comment_for "$f"; cat "$f"; } >"$tmp"
    fi
    # Keep the file's mode (executable scripts stay executable).
    cat "$tmp" >"$f"
    rm -f "$tmp"
}

# under <file>: whether the file is under one of the path arguments (all files without any).
under() {
    local p
    [[ ${#paths[@]} -eq 0 ]] && return 0
    for p in "${paths[@]}"; do
        p=${p%/}
        if [[ $p == . || $1 == "$p" || $1 == "$p"/* ]]; then
            return 0
        fi
    done
    return 1
}

paths=("$@")
missing=()
while IFS= read -r -d '' f; do
    [[ -f $f ]] || continue # deleted in the work tree
    under "$f" || continue
    if ! head -n 3 "$f" | grep -F "$id" >/dev/null; then
        if [[ $fix == 1 ]]; then
            insert "$f"
            echo "spdx: added to $f"
        else
            missing+=("$f")
        fi
    fi
done < <(git ls-files -z -- '*.c' '*.h' '*.cmake' ':(glob)**/CMakeLists.txt' '*.sh' '*.py' \
    '*.gp' '*.lcm' '*.yaml')

if [[ ${#missing[@]} -gt 0 ]]; then
    printf '%s\n' "${missing[@]}"
    echo "spdx: ${#missing[@]} file(s) without '$id' in their first 3 lines" \
        "(scripts/spdx.sh --fix adds it)" >&2
    exit 1
fi
echo "spdx: every checked file has '$id'"
