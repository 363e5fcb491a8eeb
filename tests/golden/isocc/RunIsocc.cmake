# RunIsocc.cmake - one golden test of isocc, run with `cmake -D... -P RunIsocc.cmake`.
#
#   MODE=dis    compile the program set INPUT (with INPUT/machine.json when there is one), then
#               `isocc --disasm`; stdout must equal EXPECTED
#   MODE=hex    compile INPUT, then `isocc --dump=hex`; stdout must equal EXPECTED
#   MODE=verify convert the hex fixture INPUT with HEX2IMG, then `isocc --verify NAME.isob`;
#               exit status 2 (0 for good-*.hex) and stderr must equal EXPECTED
#   MODE=determinism compile the sets in SETS from SOURCE_DIR in several ways (directory or
#               files, paths in either order, relative or absolute, another working directory,
#               twice): every image must be byte-identical
#
# ISOCC is the isocc binary; WORK a scratch directory. With ISO_UPDATE_GOLDEN=1 in the
# environment, a mismatching EXPECTED file is rewritten instead of failing (review the diff).
cmake_minimum_required(VERSION 3.20)

function(run_checked out_var err_var rc_var)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK} OUTPUT_VARIABLE o ERROR_VARIABLE e RESULT_VARIABLE r)
  set(${out_var} "${o}" PARENT_SCOPE)
  set(${err_var} "${e}" PARENT_SCOPE)
  set(${rc_var} "${r}" PARENT_SCOPE)
endfunction()

function(compare_golden actual expected)
  if(EXISTS ${expected})
    file(READ ${expected} want)
  else()
    set(want "<missing ${expected}>")
  endif()
  if("${actual}" STREQUAL "${want}")
    return()
  endif()
  if("$ENV{ISO_UPDATE_GOLDEN}" STREQUAL "1")
    file(WRITE ${expected} "${actual}")
    message(STATUS "updated ${expected}")
    return()
  endif()
  file(WRITE ${WORK}/${NAME}.actual "${actual}")
  execute_process(COMMAND diff -u ${expected} ${WORK}/${NAME}.actual OUTPUT_VARIABLE d)
  message(FATAL_ERROR "output differs from ${expected} (rerun with ISO_UPDATE_GOLDEN=1 to accept):\n${d}")
endfunction()

file(MAKE_DIRECTORY ${WORK})

if(MODE STREQUAL "dis" OR MODE STREQUAL "hex")
  # A set that comes with machine.json is compiled with it (its dialect and special M are
  # compile-time facts, SPEC §4.6).
  set(_machine)
  if(EXISTS ${INPUT}/machine.json)
    set(_machine --machine ${INPUT}/machine.json)
  endif()
  run_checked(out err rc ${ISOCC} ${INPUT} ${_machine} -o ${NAME}.isob)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "isocc ${INPUT} failed (exit ${rc}):\n${err}")
  endif()
  if(MODE STREQUAL "dis")
    run_checked(out err rc ${ISOCC} --disasm ${NAME}.isob)
  else()
    run_checked(out err rc ${ISOCC} --dump=hex ${NAME}.isob)
  endif()
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "isocc --${MODE} ${NAME}.isob failed (exit ${rc}):\n${err}")
  endif()
  compare_golden("${out}" ${EXPECTED})
elseif(MODE STREQUAL "verify")
  run_checked(out err rc ${HEX2IMG} ${INPUT} ${NAME}.isob)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "cannot convert ${INPUT}:\n${err}")
  endif()
  run_checked(out err rc ${ISOCC} --verify ${NAME}.isob)
  if(NAME MATCHES "^good-")
    set(want_rc 0)
  else()
    set(want_rc 2)
  endif()
  if(NOT rc EQUAL want_rc)
    message(FATAL_ERROR "isocc --verify ${NAME}.isob: exit ${rc}, expected ${want_rc}\nstderr:\n${err}")
  endif()
  compare_golden("${err}" ${EXPECTED})
elseif(MODE STREQUAL "determinism")
  string(REPLACE "," ";" SETS "${SETS}")
  foreach(set ${SETS})
    set(dir ${SOURCE_DIR}/samples/${set})
    file(GLOB files RELATIVE ${dir} ${dir}/*.mpf ${dir}/*.spf)
    list(SORT files)
    set(abs_files "")
    foreach(f ${files})
      list(PREPEND abs_files ${dir}/${f}) # reversed order
    endforeach()
    # 1: the directory, relative, from the source tree
    execute_process(COMMAND ${ISOCC} samples/${set} -o ${WORK}/${set}-1.isob WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE r1)
    # 2: every file by absolute path, reversed, from the scratch directory
    execute_process(COMMAND ${ISOCC} ${abs_files} -o ${set}-2.isob WORKING_DIRECTORY ${WORK} RESULT_VARIABLE r2)
    # 3: the directory with ./ and a trailing slash, from samples/
    execute_process(COMMAND ${ISOCC} ./${set}/ -o ${WORK}/${set}-3.isob WORKING_DIRECTORY ${SOURCE_DIR}/samples RESULT_VARIABLE r3)
    # 4: the same as 1, again
    execute_process(COMMAND ${ISOCC} samples/${set} -o ${WORK}/${set}-4.isob WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE r4)
    # 5: files relative to the set's directory, in directory order
    execute_process(COMMAND ${ISOCC} ${files} -o ${WORK}/${set}-5.isob WORKING_DIRECTORY ${dir} RESULT_VARIABLE r5)
    foreach(k 1 2 3 4 5)
      if(NOT r${k} EQUAL 0)
        message(FATAL_ERROR "${set}: compilation ${k} failed (exit ${r${k}})")
      endif()
    endforeach()
    foreach(k 2 3 4 5)
      execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/${set}-1.isob ${WORK}/${set}-${k}.isob RESULT_VARIABLE same)
      if(NOT same EQUAL 0)
        message(FATAL_ERROR "${set}: image ${k} differs from image 1 (see ${WORK})")
      endif()
    endforeach()
  endforeach()
else()
  message(FATAL_ERROR "RunIsocc.cmake: unknown MODE '${MODE}'")
endif()
