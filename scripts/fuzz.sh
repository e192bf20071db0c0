#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the libFuzzer targets (clang, ASan + UBSan, every sdvi module instrumented) in
# their own build directory and fuzzes one target, or all in turn, for SECONDS each in a
# low-priority process, starting from its committed seed corpus fuzz/corpus/TARGET. The
# targets read .sdvi input with ReadOptions::verify_checksums off, so that mutated inputs
# reach the checks behind the checksum; the library code is the shipped code.
# New inputs go to $FUZZ_DIR/corpus-TARGET, crashing ones to $FUZZ_DIR/artifacts-TARGET,
# with the sanitizer's report in $FUZZ_DIR/artifacts-TARGET/sanitizer.PID (printed on failure).
#   usage: scripts/fuzz.sh [SECONDS (default 600; 0 = build only)] [TARGET|all (default all)]
#   targets: decode         the .sdvi reader, DecodeSdvi (fuzz/fuzz_decode.cpp)
#            draco_payload  the Draco payload decoder alone, DecodeDracoPayload
#            compress       decode -> compress (Draco) -> decode, DecodeImage/EncodeImage
#            mesh_json      the mesh JSON reader, ParseMeshJson
#            raster         raster decode through the importer, DecodeRaster
#            svg            the SVG importer's input side, LoadSvg + RenderSvg +
#                           TraceSvgGeometry, ArtworkFeatures
#            edit_script    the edit script, ParseEditScript, applied by ApplyEdits
#   env: FUZZ_DIR (default build-fuzz), CXX_FUZZ / CC_FUZZ (default clang++ / clang),
#        FUZZ_OPT (default -O3; the optimisation of a new FUZZ_DIR: ctest's fuzz.* tests,
#        which fuzz 5 s each, build at -O0, a third of the compile time),
#        FUZZ_RSS_MB (default 2048), FUZZ_NICE (default 10), FUZZ_QUIET=1 (libFuzzer's log
#        to FUZZ_DIR/TARGET.log)
# Needs clang (Debian clang 14 and libclang-rt-14-dev). The ctest tests fuzz.* run it for
# a few seconds per target.
set -euo pipefail
cd "$(dirname "$0")/.."
RUN_SECONDS=${1:-600}
WHICH=${2:-all}
ALL_TARGETS="decode draco_payload compress mesh_json raster svg edit_script"
case "$WHICH" in
  all) TARGETS=$ALL_TARGETS ;;
  decode|draco_payload|compress|mesh_json|raster|svg|edit_script) TARGETS=$WHICH ;;
  *) echo "fuzz.sh: unknown target '$WHICH' (one of: $ALL_TARGETS, all)" >&2; exit 1 ;;
esac
FUZZ_DIR=${FUZZ_DIR:-build-fuzz}
FLAGS="-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=undefined"
FLAGS="$FLAGS -fno-omit-frame-pointer -gline-tables-only"
if [ ! -f "$FUZZ_DIR/build.ninja" ]; then
  LAUNCHER=()
  command -v ccache >/dev/null 2>&1 && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  cmake -S . -B "$FUZZ_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER="${CC_FUZZ:-clang}" -DCMAKE_CXX_COMPILER="${CXX_FUZZ:-clang++}" \
    "${LAUNCHER[@]}" -DCMAKE_C_FLAGS="$FLAGS" -DCMAKE_CXX_FLAGS="$FLAGS" \
    -DCMAKE_C_FLAGS_RELEASE="${FUZZ_OPT:--O3} -DNDEBUG" -DCMAKE_CXX_FLAGS_RELEASE="${FUZZ_OPT:--O3} -DNDEBUG" \
    -DSDVI_BUILD_FUZZ=ON -DSDVI_BUILD_TESTS=OFF -DSDVI_BUILD_BENCH=OFF -DSDVI_RASTER_MODULE=OFF >/dev/null
fi
BUILD_TARGETS=""
for t in $TARGETS; do BUILD_TARGETS="$BUILD_TARGETS fuzz_$t"; done
# shellcheck disable=SC2086
cmake --build "$FUZZ_DIR" --target $BUILD_TARGETS -- -j"${FUZZ_JOBS:-2}" >/dev/null
[ "$RUN_SECONDS" = 0 ] && exit 0
status=0
USER_ASAN_OPTIONS=${ASAN_OPTIONS:-} USER_UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
for t in $TARGETS; do
  CORPUS="$FUZZ_DIR/corpus-$t"
  ARTIFACTS="$FUZZ_DIR/artifacts-$t"
  mkdir -p "$CORPUS" "$ARTIFACTS"
  echo "fuzz.sh: fuzzing $t for ${RUN_SECONDS}s (new inputs in $CORPUS)"
  SEEDS="fuzz/corpus/$t"
  # svg: fontconfig/pango keep process-lifetime caches that LeakSanitizer would report.
  # raster: OpenImageIO's per-thread error text (fuzz/raster_lsan.supp).
  case "$t" in
    svg|raster) export LSAN_OPTIONS="suppressions=$PWD/fuzz/${t}_lsan.supp" ;;
    *) unset LSAN_OPTIONS ;;
  esac
  LOG=/dev/stderr
  [ "${FUZZ_QUIET:-0}" = 1 ] && LOG="$FUZZ_DIR/$t.log"
  # Sanitizer reports go to files of their own: raster input captures the process's stderr
  # while a library decodes, which would swallow a report printed there.
  SANITIZER_LOG="$(cd "$ARTIFACTS" && pwd)/sanitizer"
  rm -f "$SANITIZER_LOG".*
  export ASAN_OPTIONS="${USER_ASAN_OPTIONS:+$USER_ASAN_OPTIONS:}log_path=$SANITIZER_LOG"
  export UBSAN_OPTIONS="$USER_UBSAN_OPTIONS:log_path=$SANITIZER_LOG"
  # The first directory receives new inputs; the committed seeds are read only.
  nice -n "${FUZZ_NICE:-10}" "$FUZZ_DIR/fuzz/fuzz_$t" -max_total_time="$RUN_SECONDS" -max_len=65536 \
    -rss_limit_mb="${FUZZ_RSS_MB:-2048}" -timeout=60 -print_final_stats=1 \
    -artifact_prefix="$ARTIFACTS/" "$CORPUS" "$SEEDS" >"$LOG" 2>&1 || {
    echo "fuzz.sh: $t FAILED (see $LOG and $ARTIFACTS)" >&2
    [ "${FUZZ_QUIET:-0}" = 1 ] && tail -40 "$LOG" >&2
    for report in "$SANITIZER_LOG".*; do
      [ -f "$report" ] && { echo "fuzz.sh: $report:" >&2; cat "$report" >&2; }
    done
    status=1
  }
done
exit $status
