# SPDX-License-Identifier: GPL-3.0-or-later
# For the CLI tests run as `cmake -DSDVI=<sdvi> ... -P TEST.cmake`:
#   run_sdvi(EXPECTED_RC ARGS...) runs sdvi with ARGS, fails the test unless it exits with
#   EXPECTED_RC, and leaves its standard output and error in last_out and last_err.
function(run_sdvi expected_rc)
  execute_process(COMMAND ${SDVI} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL expected_rc)
    message(FATAL_ERROR "sdvi ${ARGN}: exit ${rc}, expected ${expected_rc}\n${out}\n${err}")
  endif()
  set(last_out "${out}" PARENT_SCOPE)
  set(last_err "${err}" PARENT_SCOPE)
endfunction()
