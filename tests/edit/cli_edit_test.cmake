# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test of `sdvi edit`, `sdvi info --features` and `sdvi render --overlay features`, run
# by ctest as   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_edit_test.cmake
# Checks exit codes, byte-identical identity edits (raw and Draco), that the output keeps
# the payload kind, and that every error names the key or element and leaves no output.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

# A failing edit: exit 1, stderr matching `pattern`, no output file.
function(expect_refusal pattern)
  file(REMOVE ${WORK}/bad.sdvi)
  run_sdvi(1 edit ${WORK}/s.sdvi -o ${WORK}/bad.sdvi ${ARGN})
  if(NOT last_err MATCHES "${pattern}")
    message(FATAL_ERROR "sdvi edit ${ARGN}: expected '${pattern}' in\n${last_err}")
  endif()
  if(EXISTS ${WORK}/bad.sdvi)
    message(FATAL_ERROR "sdvi edit ${ARGN} failed but left bad.sdvi")
  endif()
endfunction()

run_sdvi(0 sample -o ${WORK}/s.png --width 96 --height 64)
run_sdvi(0 vectorize ${WORK}/s.png -o ${WORK}/s.sdvi --quiet)
run_sdvi(0 compress ${WORK}/s.sdvi -o ${WORK}/c.sdvi --quiet)

# The feature table: pairs with their sharpness.
run_sdvi(0 info ${WORK}/s.sdvi --features)
if(NOT last_out MATCHES "P0 +pair")
  message(FATAL_ERROR "info --features: no pair P0 in\n${last_out}")
endif()
run_sdvi(0 info ${WORK}/c.sdvi --features --json)
string(JSON kind GET "${last_out}" features 0 kind)
string(JSON pair_id GET "${last_out}" features 0 id)
if(NOT kind STREQUAL "pair" OR NOT pair_id EQUAL 0)
  message(FATAL_ERROR "info --features --json: expected pair 0 first\n${last_out}")
endif()

# Identity edits: byte-identical, raw and Draco.
file(WRITE ${WORK}/identity.json [=[{"sdvi_edit": 1, "ops": [
  {"op": "translate", "by": [0, 0]}, {"op": "scale_color", "factor": 1},
  {"op": "hsl_shift", "hue": 0}, {"op": "affine", "matrix": [[1, 0, 0], [0, 1, 0]]}]}]=])
foreach(name s c)
  run_sdvi(0 edit ${WORK}/${name}.sdvi -o ${WORK}/${name}_same.sdvi --script ${WORK}/identity.json)
  file(SHA256 ${WORK}/${name}.sdvi want)
  file(SHA256 ${WORK}/${name}_same.sdvi got)
  if(NOT got STREQUAL want)
    message(FATAL_ERROR "identity edit of ${name}.sdvi changed the bytes")
  endif()
endforeach()

# A real edit keeps the payload kind.
run_sdvi(0 edit ${WORK}/c.sdvi -o ${WORK}/c_sharp.sdvi --sharpness 0=1 --recolor pair:0:255,0,0 --json)
string(JSON recoloured GET "${last_out}" vertices_recoloured)
if(recoloured EQUAL 0)
  message(FATAL_ERROR "--recolor changed no vertex\n${last_out}")
endif()
run_sdvi(0 info ${WORK}/c_sharp.sdvi --json)
string(JSON payload GET "${last_out}" payload)
if(NOT payload STREQUAL "draco")
  message(FATAL_ERROR "editing a Draco file gave a ${payload} payload")
endif()
run_sdvi(0 edit ${WORK}/s.sdvi -o ${WORK}/s_sharp.sdvi --sharpness 0=1)
run_sdvi(0 info ${WORK}/s_sharp.sdvi --features --json)
string(JSON sharpness GET "${last_out}" features 0 sharpness)
if(NOT sharpness EQUAL 1)
  message(FATAL_ERROR "--sharpness 0=1 left sharpness ${sharpness}")
endif()

# Bad scripts and refused edits: exit 1, the key or element named, no output.
file(WRITE ${WORK}/unknown_op.json [=[{"ops": [{"op": "explode"}]}]=])
expect_refusal("ops\\[0\\]\\.op: unknown operation \"explode\"" --script ${WORK}/unknown_op.json)
file(WRITE ${WORK}/nan.json "{\"ops\": [\n {\"op\": \"translate\", \"by\": [NaN, 0]}]}")
expect_refusal("not valid JSON.*line 2" --script ${WORK}/nan.json)
file(WRITE ${WORK}/wrong_type.json [=[{"ops": [{"op": "set_color", "rgb": [1, "2", 3]}]}]=])
expect_refusal("ops\\[0\\]\\.rgb\\[1\\]: expected a number, got string" --script ${WORK}/wrong_type.json)
file(WRITE ${WORK}/unknown_id.json [=[{"ops": [{"op": "set_sharpness", "pair": 9999, "sharpness": 1}]}]=])
expect_refusal("ops\\[0\\] \\(set_sharpness\\): pair 9999 does not exist" --script ${WORK}/unknown_id.json)
expect_refusal("not_found" --script ${WORK}/missing.json)
# Vertex 0 (a frame corner) pulled across the image folds the triangles around it.
expect_refusal("edit_refused: --move: the edit would fold the mesh: triangle [0-9]+ \\(vertices" --move 0:60,40)

# Bad flag values are usage errors (exit 2), also without output.
run_sdvi(2 edit ${WORK}/s.sdvi -o ${WORK}/bad.sdvi --sharpness 0=2)
run_sdvi(2 edit ${WORK}/s.sdvi -o ${WORK}/bad.sdvi)
if(EXISTS ${WORK}/bad.sdvi)
  message(FATAL_ERROR "a usage error left bad.sdvi")
endif()

# The overlay picture.
run_sdvi(0 render ${WORK}/s.sdvi -o ${WORK}/overlay.png --overlay features --scale 4)
if(NOT EXISTS ${WORK}/overlay.png)
  message(FATAL_ERROR "render --overlay features wrote nothing")
endif()
file(GLOB leftovers ${WORK}/.*sdvi-tmp*)
if(leftovers)
  message(FATAL_ERROR "temporary files left behind: ${leftovers}")
endif()
file(REMOVE_RECURSE ${WORK})
