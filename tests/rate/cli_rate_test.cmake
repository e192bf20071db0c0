# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test of the one-PSNR rule (spec/RATE.md 1), `sdvi info`'s bytes by part, the targets and
# `compress --reference` (the rate control for a raw file), run by ctest as
#   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_rate_test.cmake
# vectorize (with and without --compress) reports a PSNR; compare of the .sdvi and compare of
# its x1 PNG render must print the same number, and the report's MSSIM and mean error are
# compare's too.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

run_sdvi(0 sample -o ${WORK}/s.png --width 96 --height 72)
foreach(mode compress raw)
  set(flag "")
  if(mode STREQUAL "compress")
    set(flag --compress)
  endif()
  run_sdvi(0 vectorize ${WORK}/s.png -o ${WORK}/${mode}.sdvi --compression-ratio 20 --threads 1 --quiet
           --report ${WORK}/${mode}.json ${flag})
  file(READ ${WORK}/${mode}.json report)
  string(JSON reported GET "${report}" psnr_db)
  run_sdvi(0 compare ${WORK}/${mode}.sdvi ${WORK}/s.png --json)
  string(JSON from_sdvi GET "${last_out}" psnr)
  foreach(field mssim mean_error)
    string(JSON in_report GET "${report}" ${field})
    string(JSON in_compare GET "${last_out}" ${field})
    if(NOT in_report STREQUAL in_compare)
      message(FATAL_ERROR "${mode}: ${field} ${in_report} in the report, ${in_compare} from compare of the .sdvi")
    endif()
  endforeach()
  run_sdvi(0 render ${WORK}/${mode}.sdvi -o ${WORK}/${mode}.png --quiet)
  run_sdvi(0 compare ${WORK}/${mode}.png ${WORK}/s.png --json)
  string(JSON from_png GET "${last_out}" psnr)
  # Same double, printed by the same JSON writer.
  if(NOT reported STREQUAL from_sdvi OR NOT reported STREQUAL from_png)
    message(FATAL_ERROR "${mode}: three PSNRs: report ${reported}, compare .sdvi ${from_sdvi}, compare PNG ${from_png}")
  endif()
  # info: bytes by part sum to the file.
  run_sdvi(0 info ${WORK}/${mode}.sdvi --json)
  string(JSON file_bytes GET "${last_out}" file_bytes)
  set(sum 0)
  foreach(part connectivity positions colors tags feature_layer container)
    string(JSON n GET "${last_out}" bytes_by_part ${part})
    math(EXPR sum "${sum} + ${n}")
  endforeach()
  if(NOT sum EQUAL file_bytes)
    message(FATAL_ERROR "${mode}: bytes by part sum to ${sum}, the file has ${file_bytes}")
  endif()
endforeach()

# Targets (spec/RATE.md 4). Bytes: the file fits.
run_sdvi(0 vectorize ${WORK}/s.png -o ${WORK}/bytes.sdvi --target-bytes 2000 --threads 1 --quiet
         --report ${WORK}/bytes.json)
file(SIZE ${WORK}/bytes.sdvi size)
file(READ ${WORK}/bytes.json report)
string(JSON reached GET "${report}" target_reached)
if(size GREATER 2000 OR NOT reached)
  message(FATAL_ERROR "--target-bytes 2000: file of ${size} bytes, reached ${reached}")
endif()
# An unreachable PSNR: a warning, the report says so, exit 0 ...
execute_process(COMMAND ${SDVI} vectorize ${WORK}/s.png -o ${WORK}/short.sdvi --target-psnr 90 --threads 1
                        --quiet --report ${WORK}/short.json
                RESULT_VARIABLE rc ERROR_VARIABLE err)
file(READ ${WORK}/short.json report)
string(JSON reached GET "${report}" target_reached)
if(NOT rc EQUAL 0 OR reached OR NOT err MATCHES "warning: .*target PSNR 90.00 dB not reached")
  message(FATAL_ERROR "unreachable --target-psnr: exit ${rc}, reached ${reached}, stderr: ${err}")
endif()
# ... and under --strict a failure that writes nothing.
execute_process(COMMAND ${SDVI} vectorize ${WORK}/s.png -o ${WORK}/strict.sdvi --target-psnr 90 --strict
                        --threads 1 --quiet
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR EXISTS ${WORK}/strict.sdvi OR NOT err MATCHES "not reached.*nothing written")
  message(FATAL_ERROR "--strict with an unreachable target: exit ${rc}, stderr: ${err}")
endif()
# Usage errors: two targets, a quality out of range.
execute_process(COMMAND ${SDVI} vectorize ${WORK}/s.png -o ${WORK}/two.sdvi --quality 50 --target-bytes 900
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR EXISTS ${WORK}/two.sdvi OR NOT err MATCHES "excludes")
  message(FATAL_ERROR "two targets: exit ${rc}, stderr: ${err}")
endif()
execute_process(COMMAND ${SDVI} vectorize ${WORK}/s.png -o ${WORK}/q.sdvi --quality 101
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "not in range 0")
  message(FATAL_ERROR "--quality 101: exit ${rc}, stderr: ${err}")
endif()

# compress --reference: the rate control for a raw file and its source (spec/RATE.md 2, 3).
run_sdvi(0 compress ${WORK}/raw.sdvi -o ${WORK}/plain.sdvi --quiet)
run_sdvi(0 compress ${WORK}/raw.sdvi -o ${WORK}/rd.sdvi --reference ${WORK}/s.png --threads 1 --json)
string(JSON reported GET "${last_out}" psnr_db)
string(JSON refitted GET "${last_out}" rate colors_refitted)
file(SIZE ${WORK}/plain.sdvi plain_size)
file(SIZE ${WORK}/rd.sdvi rd_size)
run_sdvi(0 compare ${WORK}/rd.sdvi ${WORK}/s.png --json)
string(JSON from_sdvi GET "${last_out}" psnr)
run_sdvi(0 compare ${WORK}/plain.sdvi ${WORK}/s.png --json)
string(JSON plain_psnr GET "${last_out}" psnr)
if(NOT rd_size LESS plain_size OR NOT reported STREQUAL from_sdvi)
  message(FATAL_ERROR "compress --reference: ${rd_size} bytes (plain ${plain_size}), PSNR ${reported} reported, "
                      "${from_sdvi} from compare")
endif()
message(STATUS "compress: ${plain_size} bytes at ${plain_psnr} dB; with --reference ${rd_size} at ${reported} dB "
               "(colours refitted: ${refitted})")
# The same on any thread count.
run_sdvi(0 compress ${WORK}/raw.sdvi -o ${WORK}/rd3.sdvi --reference ${WORK}/s.png --threads 3 --quiet)
file(SHA256 ${WORK}/rd.sdvi rd_hash)
file(SHA256 ${WORK}/rd3.sdvi rd3_hash)
if(NOT rd_hash STREQUAL rd3_hash)
  message(FATAL_ERROR "compress --reference: --threads 1 and 3 give different files")
endif()
# A reference of another size: an error naming it, nothing written; explicit bits: a usage error.
run_sdvi(0 sample -o ${WORK}/small.png --width 48 --height 36)
execute_process(COMMAND ${SDVI} compress ${WORK}/raw.sdvi -o ${WORK}/bad.sdvi --reference ${WORK}/small.png
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0 OR EXISTS ${WORK}/bad.sdvi OR NOT err MATCHES "small.png: the reference is 48x36, the image 96x72")
  message(FATAL_ERROR "compress --reference of another size: exit ${rc}, stderr: ${err}")
endif()
execute_process(COMMAND ${SDVI} compress ${WORK}/raw.sdvi -o ${WORK}/bits.sdvi --reference ${WORK}/s.png
                        --position-bits 12
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR EXISTS ${WORK}/bits.sdvi OR NOT err MATCHES "excludes")
  message(FATAL_ERROR "compress --reference --position-bits: exit ${rc}, stderr: ${err}")
endif()
