#!/usr/bin/env bash
# Builds a libFuzzer target with clang, ASan and UBSan, writes a seed corpus, and fuzzes
# for N seconds in one low-priority process. Crashing inputs land in
# $FUZZ_DIR/artifacts-TARGET.
#   usage: scripts/fuzz.sh [SECONDS (default 600)] [decode|mesh_json (default decode)]
#   decode:    the .sdvi reader, DecodeSdvi (fuzz/fuzz_decode.cpp)
#   mesh_json: the mesh JSON reader, ParseMeshJson (fuzz/fuzz_mesh_json.cpp)
# Needs clang++ (Debian clang 14), flatc, libflatbuffers-dev. Does not use CMake.
set -euo pipefail
cd "$(dirname "$0")/.."
RUN_SECONDS=${1:-600}
TARGET=${2:-decode}
case "$TARGET" in
  decode|mesh_json) ;;
  *) echo "fuzz.sh: unknown target '$TARGET' (decode or mesh_json)" >&2; exit 1 ;;
esac
FUZZ_DIR=${FUZZ_DIR:-build-fuzz}
CXX=${CXX_FUZZ:-clang++}
CORPUS="$FUZZ_DIR/corpus-$TARGET"
ARTIFACTS="$FUZZ_DIR/artifacts-$TARGET"
mkdir -p "$FUZZ_DIR/generated" "$CORPUS" "$ARTIFACTS"
flatc --cpp --scoped-enums -o "$FUZZ_DIR/generated" schema/sdvi.fbs
READER="format/src/format.cpp format/src/canonical.cpp format/core/src/status.cpp format/core/src/file_util.cpp"
INCLUDES="-Iformat/include -Iformat/core/include -Iconverters/json/include -I$FUZZ_DIR/generated"
EXTRA=""
[ "$TARGET" = mesh_json ] && EXTRA="converters/json/src/mesh_json.cpp"
echo "fuzz.sh: building $FUZZ_DIR/fuzz_$TARGET"
# shellcheck disable=SC2086
$CXX -std=c++20 -O1 -g -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION \
  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  $INCLUDES "fuzz/fuzz_$TARGET.cpp" $READER $EXTRA -o "$FUZZ_DIR/fuzz_$TARGET"
if [ "$TARGET" = decode ]; then
  # shellcheck disable=SC2086
  $CXX -std=c++20 -O1 $INCLUDES fuzz/make_seeds.cpp $READER -o "$FUZZ_DIR/make_seeds"
  "$FUZZ_DIR/make_seeds" "$CORPUS"
  cp tests/data/*.sdvi "$CORPUS/" 2>/dev/null || true
else
  cp tests/data/*.json "$CORPUS/" 2>/dev/null || true
fi
echo "fuzz.sh: fuzzing $TARGET for ${RUN_SECONDS}s (corpus $CORPUS)"
nice -n 19 "$FUZZ_DIR/fuzz_$TARGET" -max_total_time="$RUN_SECONDS" -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$ARTIFACTS/" "$CORPUS"
