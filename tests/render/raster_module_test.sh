#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest render.raster_module: OpenImageIO is loaded only by commands that decode or write a
# raster (spec/RASTER_INPUT.md, "Loading"). The sdvi executable does not link it; `info`
# never loads it; `render` to PNG loads it from the module and writes the file.
#   usage: raster_module_test.sh SDVI DATA_DIR WORK_DIR
set -uo pipefail
SDVI=$1 DATA=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
if readelf -d "$SDVI" | grep NEEDED | grep -q OpenImageIO; then fail "sdvi links OpenImageIO directly"; fi
LD_DEBUG=files "$SDVI" info "$DATA/golden_v1_0.sdvi" >/dev/null 2>"$WORK/info.log" || fail "info failed"
if grep -q "libOpenImageIO" "$WORK/info.log"; then fail "sdvi info loaded OpenImageIO"; fi
LD_DEBUG=files "$SDVI" render "$DATA/golden_v1_0.sdvi" -o "$WORK/g.png" >/dev/null 2>"$WORK/render.log" ||
  fail "render failed: $(grep -v '^ *[0-9]*:' "$WORK/render.log" | head -3)"
grep -q "libsdvi_raster_oiio.so" "$WORK/render.log" || fail "render did not load libsdvi_raster_oiio.so"
grep -q "libOpenImageIO" "$WORK/render.log" || fail "render did not load OpenImageIO"
[ -s "$WORK/g.png" ] || fail "no PNG written"
# The written PNG reads back (decode through the same module).
"$SDVI" compare "$WORK/g.png" "$WORK/g.png" >/dev/null || fail "compare of the written PNG failed"
echo PASS
