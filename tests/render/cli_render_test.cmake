# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test of `sdvi render` and `sdvi compare`, run by ctest as
#   cmake -DSDVI=<sdvi> -DDATA=<tests/data> -DWORK=<scratch dir> -P cli_render_test.cmake
# Checks output sizes, the EXR header, compare's JSON, exit codes, and that a failing
# command leaves no file.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(golden ${DATA}/golden_v1_0.sdvi)  # 24 x 24

include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

# Width and height from a PNG's IHDR chunk.
function(png_size path out_w out_h)
  file(READ ${path} hex OFFSET 16 LIMIT 8 HEX)
  string(SUBSTRING "${hex}" 0 8 w)
  string(SUBSTRING "${hex}" 8 8 h)
  math(EXPR w "0x${w}")
  math(EXPR h "0x${h}")
  set(${out_w} ${w} PARENT_SCOPE)
  set(${out_h} ${h} PARENT_SCOPE)
endfunction()

function(expect_png_size path want_w want_h)
  png_size(${path} w h)
  if(NOT w EQUAL want_w OR NOT h EQUAL want_h)
    message(FATAL_ERROR "${path}: ${w}x${h}, expected ${want_w}x${want_h}")
  endif()
endfunction()

run_sdvi(0 render ${golden} -o ${WORK}/x1.png --quiet)
expect_png_size(${WORK}/x1.png 24 24)
run_sdvi(0 render ${golden} --scale 3 -o ${WORK}/x3.png --bits 16 --quiet)
expect_png_size(${WORK}/x3.png 72 72)
run_sdvi(0 render ${golden} --width 50 -o ${WORK}/w50.png --quiet)
expect_png_size(${WORK}/w50.png 50 50)
run_sdvi(0 render ${golden} --scale 3 --region 10,20,30,17 -o ${WORK}/region.png --quiet)
expect_png_size(${WORK}/region.png 30 17)

# RGB stays RGB: a full-frame colour render is an RGB PNG (IHDR colour type 2) tagged sRGB.
file(READ ${WORK}/x1.png colour_type OFFSET 25 LIMIT 1 HEX)
file(READ ${WORK}/x1.png head LIMIT 120 HEX)
string(FIND "${head}" "73524742" srgb_at)  # the sRGB chunk's type
if(NOT colour_type STREQUAL "02" OR srgb_at LESS 0)
  message(FATAL_ERROR "x1.png: colour type ${colour_type} (02 expected), sRGB chunk at ${srgb_at}")
endif()

# An EXR region keeps its place: data window (10 20) - (39 36) in the 72x72 display window.
run_sdvi(0 render ${golden} --scale 3 --region 10,20,30,17 -o ${WORK}/region.exr --quiet)
find_program(EXRHEADER exrheader)
if(EXRHEADER)
  execute_process(COMMAND ${EXRHEADER} ${WORK}/region.exr RESULT_VARIABLE rc OUTPUT_VARIABLE header)
  if(NOT rc EQUAL 0 OR NOT header MATCHES "dataWindow \\(type box2i\\): \\(10 20\\) - \\(39 36\\)" OR
     NOT header MATCHES "displayWindow \\(type box2i\\): \\(0 0\\) - \\(71 71\\)" OR header MATCHES "\n +A, ")
    message(FATAL_ERROR "region.exr: data/display window or channels wrong:\n${header}")
  endif()
endif()

# EXR with an error channel against a reference of the same size.
run_sdvi(0 render ${golden} -o ${WORK}/x1.exr --half --reference ${WORK}/x1.png --quiet)
find_program(EXRHEADER exrheader)
if(EXRHEADER)
  execute_process(COMMAND ${EXRHEADER} ${WORK}/x1.exr RESULT_VARIABLE rc OUTPUT_VARIABLE header)
  if(NOT rc EQUAL 0 OR NOT header MATCHES "error, 16-bit floating-point" OR NOT header MATCHES "R, 16-bit")
    message(FATAL_ERROR "exrheader ${WORK}/x1.exr failed or lacks channels:\n${header}")
  endif()
endif()

# compare: an image with itself; a .sdvi against its own 8-bit render (>= 50 dB).
run_sdvi(0 compare ${WORK}/x1.png ${WORK}/x1.png --json)
string(JSON psnr_type TYPE "${last_out}" psnr)
string(JSON mssim GET "${last_out}" mssim)
if(NOT psnr_type STREQUAL "NULL" OR NOT mssim EQUAL 1)
  message(FATAL_ERROR "compare of an image with itself: ${last_out}")
endif()
run_sdvi(0 compare ${golden} ${WORK}/x1.png --json)
string(JSON psnr GET "${last_out}" psnr)
string(JSON pixels GET "${last_out}" pixels)
if(psnr LESS 50 OR NOT pixels EQUAL 576)
  message(FATAL_ERROR "compare .sdvi vs its render: ${last_out}")
endif()
run_sdvi(0 compare ${WORK}/x1.png ${golden})
if(NOT last_out MATCHES "PSNR" OR NOT last_out MATCHES "MSSIM")
  message(FATAL_ERROR "compare text output: ${last_out}")
endif()

# Failures: exit codes, and no output file left behind.
run_sdvi(2 render ${golden} -o ${WORK}/bad.png --bits 12)
run_sdvi(2 render ${golden} -o ${WORK}/bad.jpg)
run_sdvi(2 render ${golden} -o ${WORK}/bad.png --region 1,2,3)
run_sdvi(2 render ${golden} -o ${WORK}/bad.png --scale 2 --width 10)
run_sdvi(2 render ${golden} -o ${WORK}/bad.png --half)
run_sdvi(1 render ${WORK}/missing.sdvi -o ${WORK}/bad.png)
run_sdvi(1 render ${golden} -o ${WORK}/bad.exr --reference ${WORK}/x3.png)  # sizes differ
run_sdvi(2 compare ${WORK}/x1.png)
run_sdvi(1 compare ${WORK}/x1.png ${WORK}/x3.png)
run_sdvi(1 compare ${WORK}/x1.png ${WORK}/missing.png)
foreach(f bad.png bad.jpg bad.exr)
  if(EXISTS ${WORK}/${f})
    message(FATAL_ERROR "a failed command left ${WORK}/${f}")
  endif()
endforeach()
