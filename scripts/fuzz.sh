#!/usr/bin/env bash
# Builds the libFuzzer target for the .sdvi reader (fuzz/fuzz_decode.cpp) with clang,
# ASan and UBSan, writes a seed corpus, and fuzzes for N seconds in one low-priority
# process. Crashing inputs land in $FUZZ_DIR/artifacts.
#   usage: scripts/fuzz.sh [SECONDS (default 600)]
# Needs clang++ (Debian clang 14), flatc, libflatbuffers-dev. Does not use CMake.
set -euo pipefail
cd "$(dirname "$0")/.."
RUN_SECONDS=${1:-600}
FUZZ_DIR=${FUZZ_DIR:-build-fuzz}
CXX=${CXX_FUZZ:-clang++}
mkdir -p "$FUZZ_DIR/generated" "$FUZZ_DIR/corpus" "$FUZZ_DIR/artifacts"
flatc --cpp --scoped-enums -o "$FUZZ_DIR/generated" schema/sdvi.fbs
READER="format/src/format.cpp format/src/canonical.cpp format/core/src/status.cpp format/core/src/file_util.cpp"
INCLUDES="-Iformat/include -Iformat/core/include -I$FUZZ_DIR/generated"
echo "fuzz.sh: building $FUZZ_DIR/fuzz_decode"
# shellcheck disable=SC2086
$CXX -std=c++20 -O1 -g -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION \
  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  $INCLUDES fuzz/fuzz_decode.cpp $READER -o "$FUZZ_DIR/fuzz_decode"
# shellcheck disable=SC2086
$CXX -std=c++20 -O1 $INCLUDES fuzz/make_seeds.cpp $READER -o "$FUZZ_DIR/make_seeds"
"$FUZZ_DIR/make_seeds" "$FUZZ_DIR/corpus"
cp tests/data/*.sdvi "$FUZZ_DIR/corpus/" 2>/dev/null || true
echo "fuzz.sh: fuzzing for ${RUN_SECONDS}s (corpus $FUZZ_DIR/corpus)"
nice -n 19 "$FUZZ_DIR/fuzz_decode" -max_total_time="$RUN_SECONDS" -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$FUZZ_DIR/artifacts/" "$FUZZ_DIR/corpus"
