#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The sanitizer pass of the test suite: unit-test executables built with GCC's
# AddressSanitizer + UndefinedBehaviorSanitizer (-O1; the first error ends the run, leaks
# included) in their own build directory, each Catch2 executable run whole.
#   usage: scripts/sanitize.sh [readers|all]
#   readers (default): the tests of everything that reads,
#            validates or writes files and of the mesh construction: format, codec,
#            hardening (the bad-input matrix), render (raster input and output), fit
#            (triangulation, where CGAL's mesher once read an uninitialised flag).
#   all:     every test executable (the whole Catch2 suite; what scripts/test.sh runs).
#   cli:     the command itself (build-asan/cli/sdvi) through the command-line tests: the
#            bad-input matrix (tests/hardening/cli_matrix.sh), the conventions
#            (tests/cli/cli_conventions_test.sh) and batch mode (tests/cli/cli_batch_test.cmake).
#            Not part of scripts/test.sh: about 300 processes, each a few seconds under ASan
#            (25 minutes on 2 cores, measured). A sanitizer report in any process fails the set,
#            whatever that process's exit code.
#   env: ASAN_BUILD_DIR (default build-asan)
# The readers are also fuzzed under ASan + UBSan by the fuzz.* tests (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
WHICH=${1:-readers}
case "$WHICH" in
  readers) TESTS="codec fit format render hardening" ;;
  all) TESTS="svg_export codec rate svg fit engine hardening render edit create format pdf cli gltf" ;;
  cli) TESTS="" ;;
  *) echo "sanitize.sh: unknown set '$WHICH' (readers, all or cli)" >&2; exit 2 ;;
esac
DIR=${ASAN_BUILD_DIR:-build-asan}
SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
LAUNCHER=()
command -v ccache >/dev/null 2>&1 && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B "$DIR" -G Ninja -DCMAKE_BUILD_TYPE=Sanitize "${LAUNCHER[@]}" \
  -DCMAKE_C_FLAGS_SANITIZE="-O1 -g1 $SAN" -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1 $SAN" \
  -DCMAKE_EXE_LINKER_FLAGS_SANITIZE="$SAN" -DCMAKE_SHARED_LINKER_FLAGS_SANITIZE="$SAN" \
  -DSDVI_BUILD_BENCH=OFF -DSDVI_RASTER_MODULE=OFF -DSDVI_BUILD_PYTHON=OFF -DSDVI_FUZZ_TESTS=OFF >/dev/null
targets=()
for t in $TESTS; do targets+=("sdvi_${t}_tests"); done
[ "$WHICH" = cli ] && targets=(sdvi)
cmake --build "$DIR" -j"$(nproc)" --target "${targets[@]}"

# The known leaks outside sdvi are suppressed: OpenImageIO's per-thread error text
# (fuzz/raster_lsan.supp) and the font stack's process-lifetime caches that librsvg's text
# uses (fuzz/svg_lsan.supp). Allocation stacks come from the fast (frame-pointer) unwinder,
# ASan's default, except where OpenImageIO's error text is reached (the hardening tests and
# the command): its suppression names a frame behind libstdc++'s, which has no frame
# pointers, so only the slow unwinder (fast_unwind_on_malloc=0) sees it. The slow unwinder
# everywhere made the runs 4.3x slower (274 s of CPU against 64; the codec tests 93 against 10).
SUPP="$(cd "$DIR" && pwd)/lsan.supp"
cat fuzz/raster_lsan.supp fuzz/svg_lsan.supp >"$SUPP"
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
SLOW_UNWIND="hardening"
export LSAN_OPTIONS=suppressions=$SUPP:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=0
if [ "$WHICH" = cli ]; then
  # Every report goes to a file of its own (a process's exit code alone cannot tell a
  # sanitizer's error from sdvi's refusal of bad input). An allocation past --max-memory
  # returns null, as without ASan, so that the limit error is tested rather than ASan's.
  LOGS="$(cd "$DIR" && pwd)/cli_sanitize" && rm -rf "$LOGS" && mkdir -p "$LOGS"
  SDVI="$(cd "$DIR" && pwd)/cli/sdvi"
  export ASAN_OPTIONS=$ASAN_OPTIONS:fast_unwind_on_malloc=0:allocator_may_return_null=1:log_path=$LOGS/asan
  export UBSAN_OPTIONS=$UBSAN_OPTIONS:log_path=$LOGS/ubsan
  run() {  # NAME COMMAND...
    if "${@:2}" >"$LOGS/$1.log" 2>&1; then echo "sanitize: $1: passed"
    else failed=$((failed + 1)); echo "sanitize: $1 FAILED; its log:" >&2; tail -20 "$LOGS/$1.log" >&2; fi
  }
  run cli_matrix bash tests/hardening/cli_matrix.sh "$SDVI" "$PWD/tests/data" "$LOGS/cli_matrix"
  run cli_conventions bash tests/cli/cli_conventions_test.sh "$SDVI" "$LOGS/cli_conventions"
  run cli_batch cmake -DSDVI="$SDVI" -DWORK="$LOGS/cli_batch" -P tests/cli/cli_batch_test.cmake
  for report in "$LOGS"/asan.* "$LOGS"/ubsan.*; do
    [ -e "$report" ] || continue
    failed=$((failed + 1))
    echo "sanitize: a sanitizer report, $report:" >&2
    head -30 "$report" >&2
  done
fi
# The executables run SANITIZE_JOBS at a time (default: the cores), in the order of TESTS
# (the longest first, as measured one at a time: svg_export 51 s of wall time, most of it
# the system's, codec 19 s of CPU, rate 18, svg 12, fit 10, the others under 4), each in
# its build directory as under ctest, every case included (the [slow] ones too).
njobs=${SANITIZE_JOBS:-$(nproc)}
for t in $TESTS; do
  while [ "$(jobs -pr | wc -l)" -ge "$njobs" ]; do wait -n || true; done
  rm -f "$DIR/tests/$t/sanitize.rc"
  options=$ASAN_OPTIONS
  [[ " $SLOW_UNWIND " == *" $t "* ]] && options=$options:fast_unwind_on_malloc=0
  (cd "$DIR/tests/$t" && rc=0 && start=$SECONDS &&
   { ASAN_OPTIONS=$options "./sdvi_${t}_tests" --reporter compact >sanitize.log 2>&1 || rc=$?; } &&
   echo "$rc $((SECONDS - start))" >sanitize.rc) &
done
wait
for t in $TESTS; do
  read -r rc seconds 2>/dev/null <"$DIR/tests/$t/sanitize.rc" || rc=missing
  if [ "$rc" = 0 ]; then
    echo "sanitize: sdvi_${t}_tests (${seconds} s): $(grep -E "^(Passed|All tests passed)" "$DIR/tests/$t/sanitize.log" | tail -1)"
  else
    failed=$((failed + 1))
    echo "sanitize: sdvi_${t}_tests FAILED; its log:" >&2
    tail -40 "$DIR/tests/$t/sanitize.log" >&2
  fi
done
[ "$failed" -eq 0 ]
