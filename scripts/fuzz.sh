#!/usr/bin/env bash
# Builds a libFuzzer target with clang, ASan and UBSan, writes a seed corpus, and fuzzes
# for N seconds in one low-priority process. Crashing inputs land in
# $FUZZ_DIR/artifacts-TARGET.
#   usage: scripts/fuzz.sh [SECONDS (default 600)] [decode|mesh_json|svg (default decode)]
#   decode:    the .sdvi reader, DecodeSdvi (fuzz/fuzz_decode.cpp)
#   mesh_json: the mesh JSON reader, ParseMeshJson (fuzz/fuzz_mesh_json.cpp)
#   svg:       the SVG importer's input side, LoadSvg + RenderSvg + TraceSvgGeometry
#              (fuzz/fuzz_svg.cpp; needs librsvg2-dev, libcairo2-dev, libxml2-dev)
# Needs clang++ (Debian clang 14), flatc, libflatbuffers-dev. Does not use CMake.
set -euo pipefail
cd "$(dirname "$0")/.."
RUN_SECONDS=${1:-600}
TARGET=${2:-decode}
case "$TARGET" in
  decode|mesh_json|svg) ;;
  *) echo "fuzz.sh: unknown target '$TARGET' (decode, mesh_json or svg)" >&2; exit 1 ;;
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
if [ "$TARGET" = svg ]; then
  # The importer's input side; librsvg, cairo and libxml2 are linked, not instrumented.
  INCLUDES="$INCLUDES -Iconverters/svg/include -Iconverters/svg/src -Iengine/fit/include -Iengine/render/include -Iengine/subdiv/include -Iengine/create/include $(pkg-config --cflags librsvg-2.0 cairo-script libxml-2.0 pango)"
  EXTRA="converters/svg/src/svg_check.cpp converters/svg/src/svg_path_data.cpp converters/svg/src/svg_document.cpp converters/svg/src/svg_trace.cpp $(pkg-config --libs librsvg-2.0 cairo-script libxml-2.0)"
fi
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
elif [ "$TARGET" = svg ]; then
  cp fuzz/svg_seeds/*.svg "$CORPUS/" 2>/dev/null || true
else
  cp tests/data/*.json "$CORPUS/" 2>/dev/null || true
fi
echo "fuzz.sh: fuzzing $TARGET for ${RUN_SECONDS}s (corpus $CORPUS)"
# svg: fontconfig/pango keep process-lifetime caches that LeakSanitizer would report.
[ "$TARGET" = svg ] && export LSAN_OPTIONS="suppressions=$PWD/fuzz/svg_lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
nice -n 19 "$FUZZ_DIR/fuzz_$TARGET" -max_total_time="$RUN_SECONDS" -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$ARTIFACTS/" "$CORPUS"
