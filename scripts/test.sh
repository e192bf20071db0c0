#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds everything (via setup.sh) and runs the whole test suite with ctest, then the
# sanitizer pass (scripts/sanitize.sh all: every Catch2 test executable and the command,
# built with ASan + UBSan in build-asan/, the executables run whole, the command through the
# command-line tests). SDVI_SANITIZE=0 skips it, SDVI_SANITIZE=readers runs
# only the tests of the readers and writers. A cold run (fresh clone, no ccache; README "Test")
# compiles sdvi three times: release (setup.sh), the fuzz targets (ctest's fuzz.build, clang
# -O0) and the sanitizer build (GCC -O1); README "Test" gives the time of each phase.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" --timeout 600
case "${SDVI_SANITIZE:-all}" in
  0) ;;
  readers) scripts/sanitize.sh readers ;;
  *) scripts/sanitize.sh all ;;
esac
