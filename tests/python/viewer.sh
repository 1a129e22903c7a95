#!/bin/sh
# SPDX-License-Identifier: BSD-3-Clause
# examples/python/viewer.py headless (matplotlib's Agg backend): inside the private network
# namespace of run_in_netns.sh, cdpr-rt runs free for 1 s while lcm-logger records and the
# live viewer renders the first CABLE_SHAPE it receives to live.png; then the viewer renders
# the last frame of the log to log.png. Both files must be PNGs of the figure's size
# (7 x 6 in at 80 dpi: 560 x 480) with a drawing in them (not a blank canvas).
# Usage: viewer.sh BUILD_DIR SOURCE_DIR WORK_DIR PYTHON
set -eu
bin=$1/apps
src=$2
w=$3
py=$4
url='udpm://239.255.76.67:7667?ttl=0'
rm -rf "$w"
mkdir -p "$w"
[ -x "$py" ] || { echo "SKIPPED: $py not found"; exit 77; }
command -v lcm-logger >/dev/null || { echo "SKIPPED: lcm-logger not found (Debian: liblcm-bin)"; exit 77; }
if ! "$py" -c 'import lcm, cdpr.cable_shape_t, matplotlib' 2> "$w/import.txt"; then
    cat "$w/import.txt"
    echo "SKIPPED: lcm, the generated types or matplotlib not importable (PYTHONPATH=${PYTHONPATH:-})"
    exit 77
fi
fail() {
    echo "FAIL: $*"
    exit 1
}
lcm-logger --lcm-url="$url" --quiet "$w/run.lcmlog" &
logger=$!
"$py" "$src/examples/python/viewer.py" --lcm-url "$url" --png "$w/live.png" --timeout 30 \
    > "$w/live.txt" 2>&1 &
viewer=$!
sleep 1
"$bin/cdpr-rt" "$src/scenarios/paper-line.yaml" --rate 100 --duration 1 --max-trials 2000 \
    --lcm-url "$url" --quiet
status=0
wait "$viewer" || status=$?
sleep 0.3
kill -INT "$logger"
wait "$logger" || true
cat "$w/live.txt"
[ "$status" -eq 0 ] || fail "the live viewer did not render a frame"
"$py" "$src/examples/python/viewer.py" --log "$w/run.lcmlog" --png "$w/log.png" ||
    fail "the viewer could not render the log"
for f in "$w/live.png" "$w/log.png"; do
    "$py" - "$f" <<'PY' || fail "$f is not the expected image"
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
w, h = struct.unpack(">II", data[16:24])
assert (w, h) == (560, 480), "size %dx%d" % (w, h)
# Decode the image data (8-bit RGBA, no interlace: matplotlib's Agg output) and count the
# pixels that are neither white nor transparent: axes, cables and text.
pos, idat = 8, b""
while pos < len(data):
    n, kind = struct.unpack(">I4s", data[pos:pos + 8])
    if kind == b"IDAT":
        idat += data[pos + 8:pos + 8 + n]
    pos += 12 + n
raw = zlib.decompress(idat)
bpp = 4 if data[25] == 6 else 3
stride = 1 + w * bpp
assert len(raw) == stride * h, "unexpected PNG layout"
prev = bytearray(w * bpp)
inked = 0
for y in range(h):
    f, line = raw[y * stride], bytearray(raw[y * stride + 1:(y + 1) * stride])
    for i in range(len(line)):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        if f == 1:
            line[i] = (line[i] + a) & 255
        elif f == 2:
            line[i] = (line[i] + b) & 255
        elif f == 3:
            line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 255
    prev = line
    for x in range(w):
        px = line[x * bpp:x * bpp + 3]
        if min(px) < 200:
            inked += 1
assert inked > 2000, "only %d drawn pixels" % inked
print("%s: PNG %dx%d, %d drawn pixels" % (sys.argv[1], w, h, inked))
PY
done
echo "PASS: the viewer rendered a live frame and a logged frame headless"
