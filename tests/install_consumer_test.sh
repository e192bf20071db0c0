#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest install_consumer: installs the build into a temporary prefix, builds examples/
# against it with find_package(sdvi) and with pkg-config, and runs the consumer on the
# built-in sample.   usage: install_consumer_test.sh SOURCE_DIR BUILD_DIR WORK_DIR [RASTER_MODULE (ON)]
set -euo pipefail
src=$1 build=$2 work=$3 raster_module=${4:-ON}
rm -rf "$work" && mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
test -x "$prefix/bin/sdvi" || { echo "FAIL: sdvi not installed"; exit 1; }
test -f "$prefix/include/sdvi/version.h" || { echo "FAIL: version.h not installed"; exit 1; }
test -f "$prefix/lib/cmake/sdvi/sdviConfig.cmake" || { echo "FAIL: no sdviConfig.cmake"; exit 1; }
# CMake consumer.
cmake -S "$src/examples" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
# The installed sdvi reads and writes PNGs with libpng and decodes other rasters (a PPM here)
# through the installed raster module (bin/../lib/sdvi).
"$prefix/bin/sdvi" sample -o "$work/sample.png" --width 96 --height 64
printf 'P6\n2 2\n255\n' >"$work/p.ppm" && printf '\377\0\0\0\377\0\0\0\377\377\377\377' >>"$work/p.ppm"
LD_DEBUG=files "$prefix/bin/sdvi" compare "$work/p.ppm" "$work/p.ppm" >/dev/null 2>"$work/compare_ld.log"
if [ "$raster_module" = ON ]; then
  grep -F "file=$prefix/bin/" "$work/compare_ld.log" | grep -q "/sdvi/libsdvi_raster_oiio.so" ||
    { echo "FAIL: the installed sdvi did not load the installed libsdvi_raster_oiio.so"; exit 1; }
fi
"$work/consumer/quickstart" "$work/sample.png" "$work/sample.sdvi" "$work/x2.png" | tee "$work/run.log"
grep -q "^sdvi [0-9.]*: [0-9]* vertices, PSNR" "$work/run.log" || { echo "FAIL: consumer output"; exit 1; }
"$prefix/bin/sdvi" info "$work/sample.sdvi" >/dev/null
# pkg-config consumer: the same source, flags from sdvi.pc.
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
pkg-config --exists sdvi || { echo "FAIL: pkg-config sdvi"; exit 1; }
test "$(pkg-config --modversion sdvi)" = "$("$prefix/bin/sdvi" --version | cut -d' ' -f2)" ||
  { echo "FAIL: pkg-config version differs from sdvi --version"; exit 1; }
c++ -std=c++20 -O1 "$src/examples/quickstart.cpp" -o "$work/quickstart_pc" \
  $(pkg-config --cflags --libs --static sdvi) >"$work/pc.log" 2>&1 || { cat "$work/pc.log"; exit 1; }
"$work/quickstart_pc" "$work/sample.png" "$work/sample_pc.sdvi" "$work/x2_pc.png" >/dev/null
cmp "$work/sample.sdvi" "$work/sample_pc.sdvi" || { echo "FAIL: the two consumers differ"; exit 1; }
echo "PASS"
