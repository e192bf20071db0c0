# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test: a vectorized file does not depend on the CPU's instruction set (spec/METHOD.md
# section 6, "Deterministic"), run by ctest as
#   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_any_cpu_test.cmake
# OpenCV picks its float filters' SIMD kernels at run time; OPENCV_CPU_DISABLE=AVX,AVX2,FMA3
# makes it pick as on a CPU without them. The built-in sample must vectorize to the same bytes
# both ways, at two budgets. Skipped on a CPU without AVX2 (nothing to compare).
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

file(READ /proc/cpuinfo cpuinfo)
if(NOT cpuinfo MATCHES "[ \t]avx2[ \n]")
  message("SKIP: this CPU has no AVX2, so OpenCV's choice of kernels cannot differ here")
  return()
endif()

run_sdvi(0 sample -o ${WORK}/sample.png)
foreach(options "" "--compression-ratio;20")
  string(MD5 tag "${options}")
  set(a ${WORK}/${tag}_native.sdvi)
  set(b ${WORK}/${tag}_baseline.sdvi)
  run_sdvi(0 vectorize ${WORK}/sample.png -o ${a} ${options} --quiet)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env OPENCV_CPU_DISABLE=AVX,AVX2,FMA3
                          ${SDVI} vectorize ${WORK}/sample.png -o ${b} ${options} --quiet
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "vectorize with OPENCV_CPU_DISABLE: exit ${rc}\n${err}")
  endif()
  file(SHA256 ${a} ha)
  file(SHA256 ${b} hb)
  if(NOT ha STREQUAL hb)
    message(FATAL_ERROR "vectorize ${options}: the file depends on the CPU's instruction set "
                        "(${a} and ${b} differ)")
  endif()
endforeach()
