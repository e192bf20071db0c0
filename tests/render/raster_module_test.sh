#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest render.raster_module: OpenImageIO is loaded only by commands that decode a raster
# other than a PNG (spec/RASTER_INPUT.md, "Loading"). The sdvi executable does not link it;
# `info` never loads it; `render` and `sample` write their PNGs and `compare` reads PNGs with
# libpng without loading it; `compare` of a PPM loads it from the module.
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
if grep -q "libOpenImageIO" "$WORK/render.log"; then fail "render to PNG loaded OpenImageIO"; fi
[ -s "$WORK/g.png" ] || fail "no PNG written"
LD_DEBUG=files "$SDVI" sample -o "$WORK/s.png" --width 32 --height 24 >/dev/null 2>"$WORK/sample.log" ||
  fail "sample failed"
if grep -q "libOpenImageIO" "$WORK/sample.log"; then fail "sample loaded OpenImageIO"; fi
# The written PNGs read back with libpng; a PPM is decoded through the module.
LD_DEBUG=files "$SDVI" compare "$WORK/g.png" "$WORK/s.png" >/dev/null 2>"$WORK/compare.log"
[ $? -le 1 ] || fail "compare of the written PNGs failed"
if grep -q "libOpenImageIO" "$WORK/compare.log"; then fail "compare of PNGs loaded OpenImageIO"; fi
printf 'P6\n2 2\n255\n' >"$WORK/p.ppm" && printf '\377\0\0\0\377\0\0\0\377\377\377\377' >>"$WORK/p.ppm"
LD_DEBUG=files "$SDVI" compare "$WORK/p.ppm" "$WORK/p.ppm" >/dev/null 2>"$WORK/ppm.log" || fail "compare of a PPM failed"
grep -q "libsdvi_raster_oiio.so" "$WORK/ppm.log" || fail "compare of a PPM did not load libsdvi_raster_oiio.so"
grep -q "libOpenImageIO" "$WORK/ppm.log" || fail "compare of a PPM did not load OpenImageIO"
echo PASS
