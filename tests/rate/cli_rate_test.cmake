# CLI test of the one-PSNR rule (spec/RATE.md 1) and `sdvi info`'s bytes by part, run by ctest as
#   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_rate_test.cmake
# vectorize --compress reports a PSNR; compare of the .sdvi and compare of its x1 PNG render
# must print the same number.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

function(run_sdvi expected_rc)
  execute_process(COMMAND ${SDVI} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expected_rc)
    message(FATAL_ERROR "sdvi ${ARGN}: exit ${rc}, expected ${expected_rc}\n${out}\n${err}")
  endif()
  set(last_out "${out}" PARENT_SCOPE)
endfunction()

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
