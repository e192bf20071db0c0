# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test of `sdvi subdivide`, run by ctest as
#   cmake -DSDVI=<sdvi> -DDATA=<tests/data> -DWORK=<scratch dir> -P cli_subdivide_test.cmake
# Checks exit codes, the PLY header and size, and that a failing command leaves no file.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

# The golden file's triangle count, from `sdvi info --json`.
run_sdvi(0 info ${DATA}/golden_v1_0.sdvi --json)
string(JSON control_triangles GET "${last_out}" triangles)

foreach(mode level limit)
  set(flag "")
  if(mode STREQUAL "limit")
    set(flag "--limit")
  endif()
  set(ply_path ${WORK}/${mode}.ply)
  run_sdvi(0 subdivide ${DATA}/golden_v1_0.sdvi --levels 2 ${flag} -o ${ply_path})
  # The 15 header lines (file(STRINGS) stops at binary bytes).
  file(STRINGS ${ply_path} lines LIMIT_COUNT 15 LENGTH_MINIMUM 1)
  list(GET lines 0 magic)
  list(GET lines 1 format)
  list(GET lines 14 last)
  if(NOT magic STREQUAL "ply" OR NOT format STREQUAL "format binary_little_endian 1.0" OR
     NOT last STREQUAL "end_header")
    message(FATAL_ERROR "${ply_path}: not a binary little-endian PLY file")
  endif()
  list(JOIN lines "\n" header)
  string(LENGTH "${header}\n" header_bytes)
  string(REGEX MATCH "element vertex ([0-9]+)" _ "${header}")
  set(vertices ${CMAKE_MATCH_1})
  string(REGEX MATCH "element face ([0-9]+)" _ "${header}")
  set(faces ${CMAKE_MATCH_1})
  math(EXPR want_faces "${control_triangles} * 16")
  if(NOT faces EQUAL want_faces)
    message(FATAL_ERROR "${ply_path}: ${faces} faces, expected ${want_faces}")
  endif()
  foreach(property "property uchar red" "property uchar tag" "property list uchar uint vertex_indices")
    if(NOT header MATCHES "${property}")
      message(FATAL_ERROR "${ply_path}: header lacks '${property}'")
    endif()
  endforeach()
  # Size: header + 16 bytes a vertex (3 floats, 4 uchar) + 13 bytes a face.
  file(SIZE ${ply_path} size)
  math(EXPR want_size "${header_bytes} + 16 * ${vertices} + 13 * ${faces}")
  if(NOT size EQUAL want_size)
    message(FATAL_ERROR "${ply_path}: ${size} bytes, expected ${want_size}")
  endif()
endforeach()

# Failures: exit codes, and no output file left behind.
run_sdvi(2 subdivide ${DATA}/golden_v1_0.sdvi --levels 9 -o ${WORK}/bad.ply)
run_sdvi(1 subdivide ${WORK}/missing.sdvi --levels 1 -o ${WORK}/bad.ply)
run_sdvi(2 subdivide ${DATA}/golden_v1_0.sdvi --levels 1)
run_sdvi(2 subdivide ${DATA}/golden_v1_0.sdvi --levels x -o ${WORK}/bad.ply)
if(EXISTS ${WORK}/bad.ply)
  message(FATAL_ERROR "a failed subdivide left ${WORK}/bad.ply")
endif()
