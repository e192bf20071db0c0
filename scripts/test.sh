#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds everything (via setup.sh) and runs the whole test suite with ctest, then the
# sanitizer pass (scripts/sanitize.sh: ASan + UBSan builds of the tests of every reader and
# writer, in build-asan/). SDVI_SANITIZE=0 skips it, SDVI_SANITIZE=all runs every test
# executable there.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j"$(nproc)" --timeout 600
case "${SDVI_SANITIZE:-readers}" in
  0) ;;
  all) scripts/sanitize.sh all ;;
  *) scripts/sanitize.sh readers ;;
esac
