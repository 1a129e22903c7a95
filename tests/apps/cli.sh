#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# The command-line conventions every app shares (apps/common/app_cli.h):
#   --version  one line "NAME X.Y.Z (git DESCRIBE)" on stdout, nothing on stderr, exit 0
#   --help     the usage on stdout, nothing on stderr, exit 0
#   a usage error: exactly one line on stderr, "NAME: what; try 'NAME --help'", nothing on
#   stdout, exit 2 -- an unknown option, a known one given an argument it does not take, an
#   unknown short option, and (when the app has one) an option missing its argument.
# Usage: cli.sh EXE NAME VERSION [OPTION-TAKING-AN-ARGUMENT]
set -eu
exe=$1
name=$2
version=$3
arg_opt=${4:-}
w=$(mktemp -d "${TMPDIR:-/tmp}/cdpr-cli.XXXXXX")
trap 'rm -rf "$w"' EXIT
fail=0
bad() {
    echo "FAIL: $name $*"
    fail=1
}

# run ARGS...: exit status in $rc, outputs in $w/out, $w/err.
run() {
    rc=0
    "$exe" "$@" >"$w/out" 2>"$w/err" || rc=$?
}

run --version
[ "$rc" -eq 0 ] || bad "--version: exit $rc"
[ ! -s "$w/err" ] || bad "--version: wrote to stderr: $(cat "$w/err")"
[ "$(wc -l <"$w/out")" -eq 1 ] || bad "--version: not one line: $(cat "$w/out")"
grep -Eq "^$name $version \(git [^ ()]+\)\$" "$w/out" ||
    bad "--version: '$(cat "$w/out")' is not '$name $version (git DESCRIBE)'"

run --help
[ "$rc" -eq 0 ] || bad "--help: exit $rc"
[ ! -s "$w/err" ] || bad "--help: wrote to stderr: $(cat "$w/err")"
grep -q "^usage: $name" "$w/out" || bad "--help: no usage line on stdout"
grep -q -- "--version" "$w/out" || bad "--help: does not list --version"

# usage_error EXPECTED-MESSAGE ARGS...
usage_error() {
    expected="$name: $1; try '$name --help'"
    shift
    run "$@"
    [ "$rc" -eq 2 ] || bad "$*: exit $rc, expected 2"
    [ ! -s "$w/out" ] || bad "$*: wrote to stdout"
    [ "$(wc -l <"$w/err")" -eq 1 ] || bad "$*: stderr is not one line: $(cat "$w/err")"
    [ "$(cat "$w/err")" = "$expected" ] || bad "$*: stderr '$(cat "$w/err")', expected '$expected'"
}
usage_error "unrecognized option '--frob'" --frob
usage_error "unrecognized option '--frob=1'" --frob=1
usage_error "option '--help' doesn't allow an argument" --help=yes
usage_error "invalid option -- 'x'" -x
if [ -n "$arg_opt" ]; then
    usage_error "option '$arg_opt' requires an argument" "$arg_opt"
fi

# Combinations an app refuses (nothing is loaded: the scenario need not exist).
case "$name" in
cdpr-rt)
    usage_error "--check-design needs --with-tracker" x.yaml --check-design
    usage_error "--priority: a whole number" x.yaml --priority 1.5
    usage_error "--max-misses-in-row: a whole number" x.yaml --max-misses-in-row 2.5
    ;;
cdpr-design)
    usage_error "--verdict takes no --at, --step-test, --check or --zoh (it checks at the apps' pose and writes nothing)" x.yaml --verdict --at 1
    usage_error "--quiet is for --verdict" x.yaml out --quiet
    ;;
esac

# A bad argument is refused with a message, never silently (each app's own options).
case "$name" in
cdpr-settle)
    run --segments ,
    [ "$rc" -eq 2 ] && grep -q "^cdpr-settle: --segments: no value in ','" "$w/err" ||
        bad "--segments ,: exit $rc, stderr '$(cat "$w/err")'"
    run --segments "$(printf '%0200d' 1)"
    [ "$rc" -eq 2 ] && grep -q "^cdpr-settle: --segments: longer than 127 characters" "$w/err" ||
        bad "--segments (200 characters): exit $rc, stderr '$(cat "$w/err")'"
    ;;
esac

[ "$fail" -eq 0 ] || exit 1
echo "PASS: $name --version, --help, usage errors"
