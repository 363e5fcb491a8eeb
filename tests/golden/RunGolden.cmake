# RunGolden.cmake: runs one golden case and compares it with its expectation files.
#
#   cmake -DTOOL=<exe> -DWORK_DIR=<dir> -DCASE=<name> [options] -P RunGolden.cmake
#
# The tool runs in WORK_DIR (so paths in its output stay relative) as
#
#   <TOOL> --color never [ARGS...] [<WORK_DIR>/<CASE>.args, one argument a line] [INPUT]
#   (without --color never when the .args file gives --color)
#
# and the case passes when
#   - stdout equals <CASE><OUT_SUFFIX>                  (OUT_SUFFIX defaults to .out),
#   - the exit code equals EXPECT_RC if given, else the number in <CASE>.rc,
#   - stderr equals <CASE>.stderr, when that file exists.
# On a mismatch a unified diff (expected -> actual) is printed; the actual output is kept
# under ACTUAL_DIR (default: the current directory) for inspection.
#
# With the environment variable ISO_UPDATE_GOLDEN=1 the expectations are rebased instead:
# the .out (and .rc, and .stderr when stderr is not empty or the file already exists) are
# rewritten from the actual run, and the case passes.
#
# Options:
#   ARGS        extra arguments before those of the .args file, separated by spaces
#   INPUT       a path appended last (the case's .mpf file or directory), may be empty
#   OUT_SUFFIX  suffix of the stdout expectation (default .out)
#   EXPECT_RC   expected exit code (then no .rc file is read or written)
#   ACTUAL_DIR  where the actual outputs are written
#   TEST_NAME   the CTest name, for the rebase hint
#
# The absolute WORK_DIR in stdout is replaced by @WORK_DIR@ before comparing.
#
# In .args files blank lines and lines starting with '#' are ignored; an argument cannot
# contain ';' (CMake's list separator).
cmake_minimum_required(VERSION 3.20)

foreach(var TOOL WORK_DIR CASE)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "RunGolden.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT DEFINED OUT_SUFFIX OR OUT_SUFFIX STREQUAL "")
  set(OUT_SUFFIX ".out")
endif()
if(NOT DEFINED TEST_NAME OR TEST_NAME STREQUAL "")
  set(TEST_NAME "${CASE}")
endif()
if(NOT DEFINED ACTUAL_DIR OR ACTUAL_DIR STREQUAL "")
  set(ACTUAL_DIR "${CMAKE_CURRENT_BINARY_DIR}")
endif()
set(update OFF)
if("$ENV{ISO_UPDATE_GOLDEN}" STREQUAL "1")
  set(update ON)
endif()

set(base "${WORK_DIR}/${CASE}")
set(expect_out_file "${base}${OUT_SUFFIX}")
set(expect_err_file "${base}.stderr")
set(expect_rc_file "${base}.rc")

# --- the command line ------------------------------------------------------------------
set(cmd "${TOOL}" --color never)
if(DEFINED ARGS AND NOT ARGS STREQUAL "")
  separate_arguments(extra UNIX_COMMAND "${ARGS}")
  list(APPEND cmd ${extra})
endif()
if(EXISTS "${base}.args")
  file(READ "${base}.args" args_text)
  string(REPLACE "\r" "" args_text "${args_text}")
  string(REPLACE "\n" ";" args_lines "${args_text}")
  foreach(line IN LISTS args_lines)
    if(line STREQUAL "" OR line MATCHES "^#")
      continue()
    endif()
    if(line MATCHES "^--color(=|$)") # a case that sets the colour itself
      list(REMOVE_ITEM cmd --color never)
    endif()
    list(APPEND cmd "${line}")
  endforeach()
endif()
if(DEFINED INPUT AND NOT INPUT STREQUAL "")
  list(APPEND cmd "${INPUT}")
endif()

execute_process(
  COMMAND ${cmd}
  WORKING_DIRECTORY "${WORK_DIR}"
  OUTPUT_VARIABLE actual_out
  ERROR_VARIABLE actual_err
  RESULT_VARIABLE actual_rc
  TIMEOUT 60)

# The usage line of --help names the program as invoked; show its plain name.
get_filename_component(tool_name "${TOOL}" NAME)
string(REPLACE "${TOOL}" "${tool_name}" actual_out "${actual_out}")
string(REPLACE "${TOOL}" "${tool_name}" actual_err "${actual_err}")
# The working directory (SARIF's originalUriBaseIds) differs between clones: @WORK_DIR@.
string(REPLACE "${WORK_DIR}" "@WORK_DIR@" actual_out "${actual_out}")

string(REPLACE ";" " " shown_cmd "${cmd}")
if(NOT actual_rc MATCHES "^[0-9]+$")
  message(FATAL_ERROR "golden ${CASE}: '${shown_cmd}' did not exit normally: ${actual_rc}\n"
                      "stderr:\n${actual_err}")
endif()

file(MAKE_DIRECTORY "${ACTUAL_DIR}")
set(actual_out_file "${ACTUAL_DIR}/${CASE}${OUT_SUFFIX}")
set(actual_err_file "${ACTUAL_DIR}/${CASE}.stderr")
file(WRITE "${actual_out_file}" "${actual_out}")
file(WRITE "${actual_err_file}" "${actual_err}")

# --- update mode -----------------------------------------------------------------------
function(write_if_changed path content)
  if(EXISTS "${path}")
    file(READ "${path}" old)
    if(old STREQUAL content)
      return()
    endif()
  endif()
  file(WRITE "${path}" "${content}")
  message(STATUS "updated ${path}")
endfunction()

if(update)
  write_if_changed("${expect_out_file}" "${actual_out}")
  if(NOT DEFINED EXPECT_RC OR EXPECT_RC STREQUAL "")
    write_if_changed("${expect_rc_file}" "${actual_rc}\n")
  elseif(NOT actual_rc EQUAL EXPECT_RC)
    message(FATAL_ERROR "golden ${CASE}: exit code ${actual_rc}, but this case must exit ${EXPECT_RC}")
  endif()
  if(EXISTS "${expect_err_file}" OR NOT actual_err STREQUAL "")
    write_if_changed("${expect_err_file}" "${actual_err}")
  endif()
  return()
endif()

# --- compare ---------------------------------------------------------------------------
find_program(DIFF_PROGRAM NAMES diff)
set(failures "")

# Prints a unified diff of expected (a file) against actual (a file).
function(show_diff what expected_file actual_file)
  file(RELATIVE_PATH label "${WORK_DIR}" "${expected_file}")
  if(DIFF_PROGRAM)
    execute_process(
      COMMAND "${DIFF_PROGRAM}" -u --label "expected/${label}" --label "actual/${label}"
              "${expected_file}" "${actual_file}"
      OUTPUT_VARIABLE d)
    message(NOTICE "--- ${what} differs:\n${d}")
  else()
    file(READ "${expected_file}" e)
    file(READ "${actual_file}" a)
    message(NOTICE "--- ${what} differs.\n=== expected:\n${e}=== actual:\n${a}=== end")
  endif()
endfunction()

if(NOT EXISTS "${expect_out_file}")
  list(APPEND failures "missing ${expect_out_file}")
  message(NOTICE "--- stdout (no expectation yet):\n${actual_out}")
else()
  file(READ "${expect_out_file}" expected_out)
  if(NOT expected_out STREQUAL actual_out)
    list(APPEND failures "stdout")
    show_diff("stdout" "${expect_out_file}" "${actual_out_file}")
  endif()
endif()

if(DEFINED EXPECT_RC AND NOT EXPECT_RC STREQUAL "")
  set(expected_rc "${EXPECT_RC}")
elseif(EXISTS "${expect_rc_file}")
  file(READ "${expect_rc_file}" expected_rc)
  string(STRIP "${expected_rc}" expected_rc)
else()
  set(expected_rc "")
  list(APPEND failures "missing ${expect_rc_file}")
endif()
if(NOT expected_rc STREQUAL "" AND NOT actual_rc EQUAL expected_rc)
  list(APPEND failures "exit code ${actual_rc}, expected ${expected_rc}")
endif()

if(EXISTS "${expect_err_file}")
  file(READ "${expect_err_file}" expected_err)
  if(NOT expected_err STREQUAL actual_err)
    list(APPEND failures "stderr")
    show_diff("stderr" "${expect_err_file}" "${actual_err_file}")
  endif()
endif()

if(failures)
  if(NOT actual_err STREQUAL "" AND NOT EXISTS "${expect_err_file}")
    message(NOTICE "--- stderr:\n${actual_err}")
  endif()
  string(REPLACE ";" ", " failures "${failures}")
  message(FATAL_ERROR "golden ${CASE} failed (${failures})\n"
                      "  command: (cd ${WORK_DIR} && ${shown_cmd})\n"
                      "  rebase the expectation with: ISO_UPDATE_GOLDEN=1 ctest -R '^${TEST_NAME}$'")
endif()
