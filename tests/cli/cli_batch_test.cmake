# SPDX-License-Identifier: GPL-3.0-or-later
# CLI test of batch mode (README "Many images", cli/batch.h), run by ctest as
#   cmake -DSDVI=<sdvi> -DWORK=<scratch dir> -P cli_batch_test.cmake
# Three generated images and one broken file in a directory:
#   - `vectorize DIR -O OUT` with -j 1 and -j 2: exit 1 (one failed, named on stderr), the
#     others byte-identical to single runs with the same options, nothing for the broken one,
#     no stray file, one JSON report line per input with the right status;
#   - a rerun skips the finished outputs; without the broken file it skips everything and
#     exits 0; --overwrite redoes them;
#   - render (a glob), compress, decompress, export-gltf, export-pdf, export-svg, import-svg
#     (a directory of SVGs written here): the same bytes as single runs;
#   - on a terminal, one progress bar over the files (none with --quiet);
#   - a per-job memory limit too small for any job fails every job (exit 1);
#   - usage errors exit 2 and write nothing.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/in)

include(${CMAKE_CURRENT_LIST_DIR}/../support/run_sdvi.cmake)

function(expect_same a b)
  file(SHA256 ${a} ha)
  file(SHA256 ${b} hb)
  if(NOT ha STREQUAL hb)
    message(FATAL_ERROR "${a} and ${b} differ")
  endif()
endfunction()

# expect_files(DIR names...): DIR holds exactly these files.
function(expect_files dir)
  file(GLOB found RELATIVE ${dir} ${dir}/*)
  list(SORT found)
  set(expected ${ARGN})
  list(SORT expected)
  if(NOT "${found}" STREQUAL "${expected}")
    message(FATAL_ERROR "${dir} holds '${found}', expected '${expected}'")
  endif()
endfunction()

# expect_report(FILE name=status...): one JSON line per input, in any order, each with the
# input's status, its output in the batch directory and the fields of batch.h.
function(expect_report report)
  file(STRINGS ${report} lines)
  list(LENGTH lines n)
  list(LENGTH ARGN expected_n)
  if(NOT n EQUAL expected_n)
    message(FATAL_ERROR "${report} has ${n} lines, expected ${expected_n}:\n${lines}")
  endif()
  foreach(pair IN LISTS ARGN)
    string(REPLACE "=" ";" pair "${pair}")
    list(GET pair 0 name)
    list(GET pair 1 want)
    set(seen 0)
    foreach(line IN LISTS lines)
      string(JSON input GET "${line}" input)
      get_filename_component(stem ${input} NAME_WE)
      if(stem STREQUAL name)
        math(EXPR seen "${seen} + 1")
        string(JSON status GET "${line}" status)
        string(JSON code GET "${line}" exit_code)
        string(JSON seconds GET "${line}" seconds)
        string(JSON output GET "${line}" output)
        if(NOT status STREQUAL want)
          message(FATAL_ERROR "${report}: ${name} is ${status}, expected ${want}:\n${line}")
        endif()
        if(want STREQUAL "failed")
          if(code EQUAL 0)
            message(FATAL_ERROR "${report}: ${name} failed with exit code 0")
          endif()
          string(JSON error GET "${line}" error)
          if(NOT error MATCHES "${name}")
            message(FATAL_ERROR "${report}: the error does not name ${name}: ${error}")
          endif()
        elseif(NOT code EQUAL 0)
          message(FATAL_ERROR "${report}: ${name} is ${status} with exit code ${code}")
        endif()
        get_filename_component(out_stem ${output} NAME_WE)
        if(NOT out_stem STREQUAL name OR seconds LESS 0)
          message(FATAL_ERROR "${report}: bad output or seconds:\n${line}")
        endif()
      endif()
    endforeach()
    if(NOT seen EQUAL 1)
      message(FATAL_ERROR "${report}: ${name} has ${seen} lines")
    endif()
  endforeach()
endfunction()

run_sdvi(0 sample -o ${WORK}/in/a.png --width 64 --height 48)
run_sdvi(0 sample -o ${WORK}/in/b.png --width 48 --height 48)
run_sdvi(0 sample -o ${WORK}/in/c.png --width 40 --height 56)
file(WRITE ${WORK}/in/broken.png "not a png")
file(WRITE ${WORK}/in/notes.txt "not an image either, and not a batch input")
# A non-default option passes through to every job.
set(opts --compression-ratio 40 --iterations 2)
foreach(name a b c)
  run_sdvi(0 vectorize ${WORK}/in/${name}.png -o ${WORK}/${name}_single.sdvi ${opts} --quiet)
endforeach()

foreach(jobs 1 2)
  set(out ${WORK}/out${jobs})
  # Not --quiet: stderr is not a terminal, so no progress bar; the summary goes to stdout.
  run_sdvi(1 vectorize ${WORK}/in -O ${out} -j ${jobs} ${opts} --batch-report ${WORK}/report${jobs}.jsonl)
  if(NOT last_err MATCHES "broken.png")
    message(FATAL_ERROR "-j ${jobs}: the failing input is not named:\n${last_err}")
  endif()
  if(last_err MATCHES "\r")
    message(FATAL_ERROR "-j ${jobs}: a progress bar on a stderr that is not a terminal")
  endif()
  if(NOT last_out MATCHES "3 done, 0 skipped \\(output exists\\), 1 failed")
    message(FATAL_ERROR "-j ${jobs}: summary '${last_out}'")
  endif()
  foreach(name a b c)
    expect_same(${out}/${name}.sdvi ${WORK}/${name}_single.sdvi)
  endforeach()
  expect_files(${out} a.sdvi b.sdvi c.sdvi)
  expect_report(${WORK}/report${jobs}.jsonl a=ok b=ok c=ok broken=failed)
endforeach()

# Resumable: the finished outputs are skipped, the broken input fails again.
run_sdvi(1 vectorize ${WORK}/in -O ${WORK}/out2 -j 2 ${opts} --batch-report ${WORK}/rerun.jsonl --quiet)
expect_report(${WORK}/rerun.jsonl a=skipped b=skipped c=skipped broken=failed)
if(NOT last_out STREQUAL "")
  message(FATAL_ERROR "--quiet printed '${last_out}'")
endif()
file(REMOVE ${WORK}/in/broken.png)
run_sdvi(0 vectorize ${WORK}/in -O ${WORK}/out2 -j 2 ${opts} --batch-report ${WORK}/rerun2.jsonl --quiet)
expect_report(${WORK}/rerun2.jsonl a=skipped b=skipped c=skipped)
file(WRITE ${WORK}/out2/a.sdvi "stale")
run_sdvi(0 vectorize ${WORK}/in -O ${WORK}/out2 -j 2 ${opts} --overwrite --batch-report ${WORK}/over.jsonl --quiet)
expect_report(${WORK}/over.jsonl a=ok b=ok c=ok)
expect_same(${WORK}/out2/a.sdvi ${WORK}/a_single.sdvi)

# On a terminal (script(1) gives the batch a pseudo-terminal): one progress bar over the
# files, none of the jobs' own bars; --quiet: none at all.
string(REPLACE ";" " " opts_text "${opts}")
foreach(quiet "" "--quiet")
  execute_process(COMMAND script -qec "${SDVI} vectorize ${WORK}/in -O ${WORK}/tty${quiet} -j 2 ${opts_text} ${quiet}" /dev/null
                  RESULT_VARIABLE rc OUTPUT_VARIABLE tty)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "batch on a terminal: exit ${rc}\n${tty}")
  endif()
  string(REGEX MATCHALL "vectorize 3 files done" bars "${tty}")
  list(LENGTH bars n)
  if((quiet STREQUAL "" AND NOT n EQUAL 1) OR (quiet STREQUAL "--quiet" AND NOT tty STREQUAL "")
     OR tty MATCHES "triangulate|features")
    message(FATAL_ERROR "batch ${quiet} on a terminal printed:\n${tty}")
  endif()
endforeach()

# The other commands: a batch writes what the single command writes.
run_sdvi(0 render "${WORK}/out2/*.sdvi" -O ${WORK}/png --scale 2 -j 2 --quiet)
run_sdvi(0 render "${WORK}/out2/*.sdvi" -O ${WORK}/exr --format exr --half --quiet)
run_sdvi(0 compress ${WORK}/out2 -O ${WORK}/small -j 2 --speed 5 --quiet)
run_sdvi(0 decompress ${WORK}/small -O ${WORK}/raw --quiet)
run_sdvi(0 export-gltf ${WORK}/out2/a.sdvi ${WORK}/out2/b.sdvi -O ${WORK}/glb --levels 2 --quiet)
run_sdvi(0 export-pdf ${WORK}/out2 -O ${WORK}/pdf --dpi 150 --quiet)
run_sdvi(0 export-svg ${WORK}/out2 -O ${WORK}/svgout --levels 1 --quiet)
# import-svg over a directory of SVGs written here.
file(MAKE_DIRECTORY ${WORK}/svgin)
file(WRITE ${WORK}/svgin/disc.svg "<svg xmlns='http://www.w3.org/2000/svg' width='64' height='48'><rect width='64' height='48' fill='#20a040'/><circle cx='30' cy='24' r='14' fill='#e03020'/></svg>\n")
file(WRITE ${WORK}/svgin/bars.svg "<svg xmlns='http://www.w3.org/2000/svg' width='64' height='48'><rect width='64' height='48' fill='#ffffff'/><rect x='8' y='6' width='20' height='36' fill='#3050d0'/><path d='M36 6L58 42' stroke='#000' stroke-width='2'/></svg>\n")
run_sdvi(0 import-svg ${WORK}/svgin -O ${WORK}/svgsdvi -j 2 --quiet)
foreach(name disc bars)
  run_sdvi(0 import-svg ${WORK}/svgin/${name}.svg -o ${WORK}/${name}_single.sdvi --quiet)
  expect_same(${WORK}/svgsdvi/${name}.sdvi ${WORK}/${name}_single.sdvi)
endforeach()
foreach(name a)
  run_sdvi(0 render ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_single.png --scale 2 --quiet)
  expect_same(${WORK}/png/${name}.png ${WORK}/${name}_single.png)
  run_sdvi(0 render ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_single.exr --half --quiet)
  expect_same(${WORK}/exr/${name}.exr ${WORK}/${name}_single.exr)
  run_sdvi(0 compress ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_small.sdvi --speed 5 --quiet)
  expect_same(${WORK}/small/${name}.sdvi ${WORK}/${name}_small.sdvi)
  run_sdvi(0 decompress ${WORK}/${name}_small.sdvi -o ${WORK}/${name}_raw.sdvi --quiet)
  expect_same(${WORK}/raw/${name}.sdvi ${WORK}/${name}_raw.sdvi)
  run_sdvi(0 export-gltf ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_single.glb --levels 2 --quiet)
  expect_same(${WORK}/glb/${name}.glb ${WORK}/${name}_single.glb)
  run_sdvi(0 export-pdf ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_single.pdf --dpi 150 --quiet)
  expect_same(${WORK}/pdf/${name}.pdf ${WORK}/${name}_single.pdf)
  run_sdvi(0 export-svg ${WORK}/out2/${name}.sdvi -o ${WORK}/${name}_single.svg --levels 1 --quiet)
  expect_same(${WORK}/svgout/${name}.svg ${WORK}/${name}_single.svg)
endforeach()
expect_files(${WORK}/png a.png b.png c.png)
expect_files(${WORK}/pdf a.pdf b.pdf c.pdf)
expect_files(${WORK}/svgout a.svg b.svg c.svg)
expect_files(${WORK}/glb a.glb b.glb)

# A per-job memory limit the jobs do not fit in (vectorizing 3 megapixels takes well over
# 64 MiB; a small PNG alone fits, as it loads no raster module): every job is stopped, the
# report says why, nothing is left in the output directory.
file(MAKE_DIRECTORY ${WORK}/big)
run_sdvi(0 sample -o ${WORK}/big/d.png --width 2000 --height 1500)
run_sdvi(0 sample -o ${WORK}/big/e.png --width 1500 --height 2000)
run_sdvi(1 vectorize ${WORK}/big -O ${WORK}/tight --max-memory-per-job 64M --batch-report ${WORK}/tight.jsonl --quiet)
expect_report(${WORK}/tight.jsonl d=failed e=failed)
file(READ ${WORK}/tight.jsonl tight)
if(NOT tight MATCHES "over the memory limit of 64 MiB per job")
  message(FATAL_ERROR "the memory limit is not named in the report:\n${tight}")
endif()
expect_files(${WORK}/tight)

# Usage errors (exit 2), nothing written.
run_sdvi(2 vectorize ${WORK}/in/a.png ${WORK}/in/b.png -o ${WORK}/x.sdvi)  # several inputs need -O
run_sdvi(2 vectorize ${WORK}/in/a.png)                                     # neither -o nor -O
run_sdvi(2 vectorize ${WORK}/in -o ${WORK}/x.sdvi)                         # a directory needs -O
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad -o ${WORK}/x.sdvi)          # -o and -O
run_sdvi(2 vectorize ${WORK}/in/a.png -o ${WORK}/x.sdvi -j 2)              # -j without -O
run_sdvi(2 vectorize ${WORK}/in/a.png -o ${WORK}/x.sdvi --overwrite)
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad -j 0)
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad --max-memory-per-job 1M)
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad --max-memory-per-job lots)
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad --report ${WORK}/r.json)     # one report, many inputs
run_sdvi(2 vectorize ${WORK}/in -O ${WORK}/bad --debug-dir ${WORK}/dbg)
run_sdvi(2 render ${WORK}/out2 -O ${WORK}/bad --json)
run_sdvi(2 compress - -O ${WORK}/bad)
if(EXISTS ${WORK}/x.sdvi OR EXISTS ${WORK}/bad OR EXISTS ${WORK}/r.json OR EXISTS ${WORK}/dbg)
  message(FATAL_ERROR "a usage error wrote an output")
endif()
# Refused before any job: an input that would be its own output, a missing input.
run_sdvi(1 compress ${WORK}/out2 -O ${WORK}/out2)
run_sdvi(1 vectorize ${WORK}/in/missing.png -O ${WORK}/bad)
if(NOT last_err MATCHES "missing.png")
  message(FATAL_ERROR "a missing input is not named:\n${last_err}")
endif()
