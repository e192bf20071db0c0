#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs every package sdvi needs (Debian 12, as root, no prompts), then configures
# and builds Release into build/. Idempotent: re-running only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(build-essential cmake ninja-build pkg-config
  libflatbuffers-dev flatbuffers-compiler libdraco-dev libtinygltf-dev libopenexr-dev
  libopencv-dev libcgal-dev libeigen3-dev catch2 nlohmann-json3-dev libcli11-dev)
# Image input (converters/raster): OpenImageIO (EXIF orientation, GIF, EXR, HDR), Little CMS
# (ICC -> sRGB), libpng (PNG output); giflib and zlib build the raster-input tests' files. openimageio-tools too:
# libopenimageio-dev's CMake package names its programs (/usr/bin/iconvert, ...) as imported
# targets and find_package(OpenImageIO) fails without them (only recommended, not required).
PACKAGES+=(libopenimageio-dev openimageio-tools liblcms2-dev libgif-dev zlib1g-dev libpng-dev)
# The Python binding and its Dask driver (python/): pybind11, numpy, dask.distributed.
PACKAGES+=(pybind11-dev python3-dev python3-numpy python3-dask python3-distributed)
# Tools used by tests and benchmarks: exrheader (openexr), cjpeg (libjpeg-turbo-progs),
# cwebp (webp), clang for the fuzz target, OpenSubdiv as a benchmark peer, node/npm for
# the glTF validator and the three.js viewer test, chromium for the viewer test.
PACKAGES+=(openexr libjpeg-turbo-progs webp libosd-dev clang libclang-rt-14-dev chromium)
# SVG import (converters/svg): librsvg, cairo (script surface), libxml2; rsvg-convert for
# bench_svg; Roboto for the W3C reference PNGs (bench/svg/w3c_fonts.conf).
PACKAGES+=(librsvg2-dev libcairo2-dev libpango1.0-dev libxml2-dev librsvg2-bin fonts-roboto-unhinted)
# Codecs bench_rd compares with: avifenc/avifdec, cjxl/djxl.
PACKAGES+=(libavif-bin libjxl-tools)
# Node.js: any install will do (the machine may carry a newer one than Debian's).
command -v npm >/dev/null 2>&1 || PACKAGES+=(nodejs npm)
# PDF export (converters/pdf): qpdf's library and zlib; the PDF tests' viewers and checker
# (poppler-utils: pdftoppm, pdftocairo; mupdf-tools: mutool; qpdf --check); cairo for
# bench_pdf's ShadingType 7 baseline.
PACKAGES+=(libqpdf-dev zlib1g-dev qpdf poppler-utils mupdf-tools libcairo2-dev)
if [ -n "${SDVI_EXTRA_PACKAGES:-}" ]; then PACKAGES+=(${SDVI_EXTRA_PACKAGES}); fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" </dev/null
fi

# npm tools for the glTF tests (validator, three.js), installed locally and offline-safe.
# Installed when missing, or again when package.json changed since the last install.
if [ -f scripts/npm/package.json ] && { [ ! -d scripts/npm/node_modules ] ||
     [ scripts/npm/package.json -nt scripts/npm/node_modules/.package-lock.json ]; }; then
  (cd scripts/npm && npm install --no-audit --no-fund --silent </dev/null) || \
    echo "warning: npm install failed; glTF viewer/validator tests will be skipped" >&2
fi

BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j"$(nproc)"
echo "built: $BUILD_DIR/cli/sdvi"
