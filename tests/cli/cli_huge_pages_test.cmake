# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test: `sdvi vectorize` runs itself again with glibc.malloc.hugetlb=1 added to
# GLIBC_TUNABLES (spec/METHOD.md section 6, "Memory pages"); run by ctest as
#   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_huge_pages_test.cmake
# The run again must keep the command's arguments and the user's other tunables and write the
# same bytes as a run that keeps 4 KiB pages (the user's glibc.malloc.hugetlb=0 is kept).
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

run_sdvi(0 sample -o ${WORK}/sample.png)
set(runs "plain" "glibc.malloc.hugetlb=0" "glibc.malloc.hugetlb=1" "glibc.malloc.perturb=0")
foreach(tunables ${runs})
  string(MD5 tag "${tunables}")
  if(tunables STREQUAL "plain")
    set(env --unset=GLIBC_TUNABLES)
  else()
    set(env GLIBC_TUNABLES=${tunables})
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env}
                          ${SDVI} vectorize ${WORK}/sample.png -o ${WORK}/${tag}.sdvi --iterations 1
                          --json --quiet
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "vectorize with GLIBC_TUNABLES '${tunables}': exit ${rc}\n${err}")
  endif()
  string(JSON iterations GET "${out}" iterations)
  string(JSON output GET "${out}" output)
  if(NOT iterations EQUAL 1 OR NOT output STREQUAL "${WORK}/${tag}.sdvi")
    message(FATAL_ERROR "vectorize with GLIBC_TUNABLES '${tunables}': the arguments were lost "
                        "(${iterations} iterations, asked 1; output ${output})")
  endif()
  file(SHA256 ${WORK}/${tag}.sdvi hash)
  list(APPEND hashes ${hash})
endforeach()
list(REMOVE_DUPLICATES hashes)
list(LENGTH hashes n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "vectorize wrote different files with different GLIBC_TUNABLES (${WORK})")
endif()
