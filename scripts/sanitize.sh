#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The sanitizer pass of the test suite: the Catch2 test executables and the command itself,
# built with GCC's AddressSanitizer + UndefinedBehaviorSanitizer (-O1; the first error ends
# the run, leaks included) in their own build directory; each executable runs whole.
#   usage: scripts/sanitize.sh [readers|all|cli]
#   readers (default): the tests of everything that reads,
#            validates or writes files and of the mesh construction: format, codec,
#            hardening (the bad-input matrix), render (raster input and output), fit
#            (triangulation, where CGAL's mesher once read an uninitialised flag).
#   cli:     the command (build-asan/cli/sdvi) through the command-line tests: the bad-input
#            matrix (tests/hardening/cli_matrix.sh), the conventions
#            (tests/cli/cli_conventions_test.sh) and batch mode (tests/cli/cli_batch_test.cmake),
#            about 300 processes. A sanitizer report in any process fails the set, whatever
#            that process's exit code.
#   all:     every test executable and the cli set (what scripts/test.sh runs).
#   env: ASAN_BUILD_DIR (default build-asan), SANITIZE_JOBS (default the cores)
# The readers are also fuzzed under ASan + UBSan by the fuzz.* tests (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
WHICH=${1:-readers}
CLI_SET="cli_matrix cli_batch cli_conventions"
case "$WHICH" in
  readers) TESTS="codec fit format render hardening" ;;
  all) TESTS="cli_matrix cli_batch cli_conventions codec svg rate fit engine render hardening svg_export edit cli create format pdf gltf" ;;
  cli) TESTS=$CLI_SET ;;
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
for t in $TESTS; do
  case " $CLI_SET " in
    *" $t "*) [[ " ${targets[*]} " == *" sdvi "* ]] || targets+=(sdvi) ;;
    *) targets+=("sdvi_${t}_tests") ;;
  esac
done
cmake --build "$DIR" -j"$(nproc)" --target "${targets[@]}"

# The known leaks outside sdvi are suppressed: OpenImageIO's per-thread error text
# (fuzz/raster_lsan.supp) and the font stack's process-lifetime caches that librsvg's text
# uses (fuzz/svg_lsan.supp). Allocation stacks come from the fast (frame-pointer) unwinder,
# ASan's default, except in the hardening tests, which reach OpenImageIO's error text: its
# suppression names a frame behind libstdc++'s, which has no frame pointers, so only the
# slow unwinder (fast_unwind_on_malloc=0) sees it. The slow unwinder everywhere made the
# executables 4.3x slower (274 s of CPU against 64; the codec tests 93 against 10) and the
# cli set 25 minutes on 2 cores instead of about 3.
SUPP="$(cd "$DIR" && pwd)/lsan.supp"
cat fuzz/raster_lsan.supp fuzz/svg_lsan.supp >"$SUPP"
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
SLOW_UNWIND="hardening"
export LSAN_OPTIONS=suppressions=$SUPP:print_suppressions=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The cli set: every sanitizer report goes to a file of its own (a process's exit code alone
# cannot tell a sanitizer's error from sdvi's refusal of bad input). An allocation past
# --max-memory returns null, as without ASan, so that the limit error is tested rather than
# ASan's.
LOGS="$(cd "$DIR" && pwd)/sanitize"
rm -rf "$LOGS" && mkdir -p "$LOGS"
SDVI="$(cd "$DIR" && pwd)/cli/sdvi"
job() {  # NAME: runs one executable or one command-line test, its log and rc in $LOGS
  local t=$1 rc=0 start=$SECONDS options=$ASAN_OPTIONS
  [[ " $SLOW_UNWIND " == *" $t "* ]] && options=$options:fast_unwind_on_malloc=0
  local cli_options=$ASAN_OPTIONS:allocator_may_return_null=1:log_path=$LOGS/asan
  local cli_ubsan=$UBSAN_OPTIONS:log_path=$LOGS/ubsan
  case $t in
    cli_matrix) SDVI_SANITIZED=1 ASAN_OPTIONS=$cli_options UBSAN_OPTIONS=$cli_ubsan \
      bash tests/hardening/cli_matrix.sh "$SDVI" "$PWD/tests/data" "$LOGS/$t.work" >"$LOGS/$t.log" 2>&1 || rc=$? ;;
    cli_conventions) ASAN_OPTIONS=$cli_options UBSAN_OPTIONS=$cli_ubsan \
      bash tests/cli/cli_conventions_test.sh "$SDVI" "$LOGS/$t.work" >"$LOGS/$t.log" 2>&1 || rc=$? ;;
    cli_batch) ASAN_OPTIONS=$cli_options UBSAN_OPTIONS=$cli_ubsan \
      cmake -DSDVI="$SDVI" -DWORK="$LOGS/$t.work" -P tests/cli/cli_batch_test.cmake >"$LOGS/$t.log" 2>&1 || rc=$? ;;
    *) (cd "$DIR/tests/$t" && ASAN_OPTIONS=$options "./sdvi_${t}_tests" --reporter compact) >"$LOGS/$t.log" 2>&1 || rc=$? ;;
  esac
  echo "$rc $((SECONDS - start))" >"$LOGS/$t.rc"
}
# SANITIZE_JOBS run at a time, in the order of TESTS (the longest first, as measured in a
# CI run on 2 cores, two at a time: cli_matrix 347 s, cli_batch 130 s, cli_conventions 93 s,
# codec 46 s, svg 40, rate 25, fit 24, engine 15, the others under 10; svg_export 5-7 s since
# its SVG buffer doubles, 336 s before: spec/SVG_EXPORT.md); each executable in its build
# directory as under ctest, every case included (the [slow] ones too).
njobs=${SANITIZE_JOBS:-$(nproc)}
for t in $TESTS; do
  while [ "$(jobs -pr | wc -l)" -ge "$njobs" ]; do wait -n || true; done
  job "$t" &
done
wait
failed=0
for t in $TESTS; do
  read -r rc seconds 2>/dev/null <"$LOGS/$t.rc" || rc=missing
  name=$t
  [[ " $CLI_SET " == *" $t "* ]] || name=sdvi_${t}_tests
  if [ "$rc" = 0 ]; then
    summary=$(grep -E "^(Passed|All tests passed|cli matrix:)" "$LOGS/$t.log" | tail -1 || true)
    echo "sanitize: $name (${seconds} s): ${summary:-passed}"
  else
    failed=$((failed + 1))
    echo "sanitize: $name FAILED; its log:" >&2
    tail -40 "$LOGS/$t.log" >&2
  fi
done
for report in "$LOGS"/asan.* "$LOGS"/ubsan.*; do
  [ -e "$report" ] || continue
  failed=$((failed + 1))
  echo "sanitize: a sanitizer report, $report:" >&2
  head -30 "$report" >&2
done
[ "$failed" -eq 0 ]
