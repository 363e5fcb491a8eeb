# golden.cmake: file-based end-to-end tests (STYLE habits 11 and 15), included by
# tests/CMakeLists.txt. Every case is its own CTest test:
#
#   golden/isolint/<case>   tests/golden/isolint/<case>.{mpf|args|out|rc|stderr} (README.md)
#   golden/help/<tool>      tests/golden/help/<tool>.txt: the tool's --help (keeps man/ in step)
#   golden/man/isolint      man/isolint.1 documents every option and rule; its examples trigger
#                           their rules; groff -man -ww is silent
#   sarif/schema            isolint --format sarif validated against tests/schemas/sarif-2.1.0.json
#   corpus/isolint          isolint --format json on every file of ../shared/corpus (SKIP if absent)
#
# Rebase expectations with: ISO_UPDATE_GOLDEN=1 ctest -R golden/isolint
set(ISO_GOLDEN_DIR ${CMAKE_CURRENT_LIST_DIR})
set(ISO_GOLDEN_RUNNER ${ISO_GOLDEN_DIR}/RunGolden.cmake)
set(ISO_TEST_PYTHON /usr/bin/python3 CACHE FILEPATH
    "Python 3 with Debian's python3-jsonschema, for the sarif/schema and corpus tests")

# One test per case of tests/golden/<tool>/. A case is named by any of <case>.mpf,
# <case>.args or <case>.out; its input is <case>.mpf, else the directory <case>/ (a
# multi-file program set), else nothing (the .args name the inputs). Other files and
# directories there (machine files, shared program sets) are only data.
function(iso_add_golden_suite tool)
  set(dir ${ISO_GOLDEN_DIR}/${tool})
  file(GLOB files CONFIGURE_DEPENDS RELATIVE ${dir} ${dir}/*.mpf ${dir}/*.args ${dir}/*.out)
  set(cases "")
  foreach(f IN LISTS files)
    string(REGEX REPLACE "\\.(mpf|args|out)$" "" c "${f}")
    list(APPEND cases "${c}")
  endforeach()
  list(REMOVE_DUPLICATES cases)
  list(SORT cases)
  foreach(c IN LISTS cases)
    set(input "")
    if(EXISTS ${dir}/${c}.mpf)
      set(input "${c}.mpf")
    elseif(IS_DIRECTORY ${dir}/${c})
      set(input "${c}")
    endif()
    add_test(NAME golden/${tool}/${c}
             COMMAND ${CMAKE_COMMAND}
                     -DTOOL=$<TARGET_FILE:${tool}>
                     -DWORK_DIR=${dir}
                     -DCASE=${c}
                     -DINPUT=${input}
                     -DTEST_NAME=golden/${tool}/${c}
                     -DACTUAL_DIR=${CMAKE_CURRENT_BINARY_DIR}/golden-actual/${tool}
                     -P ${ISO_GOLDEN_RUNNER})
    set_tests_properties(golden/${tool}/${c} PROPERTIES LABELS golden TIMEOUT 120)
  endforeach()
endfunction()

# --help golden: tests/golden/help/<tool>.txt, exit code 0.
function(iso_add_help_golden tool)
  add_test(NAME golden/help/${tool}
           COMMAND ${CMAKE_COMMAND}
                   -DTOOL=$<TARGET_FILE:${tool}>
                   -DWORK_DIR=${ISO_GOLDEN_DIR}/help
                   -DCASE=${tool}
                   -DARGS=--help
                   -DOUT_SUFFIX=.txt
                   -DEXPECT_RC=0
                   -DTEST_NAME=golden/help/${tool}
                   -DACTUAL_DIR=${CMAKE_CURRENT_BINARY_DIR}/golden-actual/help
                   -P ${ISO_GOLDEN_RUNNER})
  set_tests_properties(golden/help/${tool} PROPERTIES LABELS golden TIMEOUT 60)
endfunction()

if(TARGET isolint)
  iso_add_golden_suite(isolint)
  iso_add_help_golden(isolint)
  iso_add_help_golden(isocc)
  iso_add_golden_suite(isofmt)
  iso_add_help_golden(isofmt)

  # -j 2 must print exactly what -j 1 prints: the two expectations must stay identical
  # (a rebase of one alone would hide a difference).
  add_test(NAME golden/isolint/parallel-same-output
           COMMAND ${CMAKE_COMMAND} -E compare_files
                   ${ISO_GOLDEN_DIR}/isolint/parallel-j1.out ${ISO_GOLDEN_DIR}/isolint/parallel-j2.out)
  set_tests_properties(golden/isolint/parallel-same-output PROPERTIES LABELS golden)

  # The manual page against --help, the rule table and isolint itself.
  add_test(NAME golden/man/isolint
           COMMAND ${ISO_TEST_PYTHON} ${ISO_GOLDEN_DIR}/check_man_isolint.py
                   --man ${PROJECT_SOURCE_DIR}/man/isolint.1
                   --help-golden ${ISO_GOLDEN_DIR}/help/isolint.txt
                   --diagnostics ${PROJECT_SOURCE_DIR}/lib/diag/Diagnostics.def
                   --tool $<TARGET_FILE:isolint>)
  set_tests_properties(golden/man/isolint PROPERTIES LABELS golden TIMEOUT 120)

  # SARIF 2.1.0 schema check (tests/schemas/README.md). Runs from the golden case
  # directory so that the inputs are relative paths, as users pass them.
  add_test(NAME sarif/schema
           COMMAND ${ISO_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/schemas/validate_sarif.py
                   --schema ${PROJECT_SOURCE_DIR}/tests/schemas/sarif-2.1.0.json
                   --tool $<TARGET_FILE:isolint>
                   diagnostics.mpf set-calls clean.mpf
           WORKING_DIRECTORY ${ISO_GOLDEN_DIR}/isolint)
  set_tests_properties(sarif/schema PROPERTIES LABELS schema TIMEOUT 120)

  # Robustness on real programs written by others; skipped when ../shared/corpus is absent.
  add_test(NAME corpus/isolint
           COMMAND ${ISO_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/corpus/run_corpus.py
                   --tool $<TARGET_FILE:isolint>
                   --corpus ${PROJECT_SOURCE_DIR}/../shared/corpus
                   --max-seconds 5)
  set_tests_properties(corpus/isolint PROPERTIES LABELS corpus TIMEOUT 600 SKIP_RETURN_CODE 77)
endif()

# Every man page: --help options documented and groff -man -ww clean (isosim is added by
# isosim.cmake when present); the section 5 and 7 pages only need to be groff clean.
foreach(tool isolint isocc isofmt)
  add_test(NAME man/${tool}
           COMMAND ${ISO_TEST_PYTHON} ${ISO_GOLDEN_DIR}/check_man_options.py
                   ${PROJECT_SOURCE_DIR}/man/${tool}.1 ${ISO_GOLDEN_DIR}/help/${tool}.txt)
  set_tests_properties(man/${tool} PROPERTIES LABELS man)
endforeach()
foreach(page iso.7 isoimage.5)
  add_test(NAME man/${page} COMMAND groff -man -ww -z ${PROJECT_SOURCE_DIR}/man/${page})
  set_tests_properties(man/${page} PROPERTIES LABELS man FAIL_REGULAR_EXPRESSION ".")
endforeach()

# JSON Schemas of schemas/ (schemas/README.md): isolint --format json, isosim's summary,
# --profile and JSON trace, and the machine file, validated on real runs; skipped (77)
# without python3-jsonschema.
add_test(NAME schema/outputs COMMAND ${ISO_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/schemas/validate_outputs.py --schemas ${PROJECT_SOURCE_DIR}/schemas --bin $<TARGET_FILE_DIR:isolint> --source ${PROJECT_SOURCE_DIR})
set_tests_properties(schema/outputs PROPERTIES LABELS schema TIMEOUT 120 SKIP_RETURN_CODE 77)

# isolint --fix on a copy of tests/fixes/ (every fixable diagnostic, LF and CR LF files, Latin-1
# comments): what is fixed, what is kept byte for byte, idempotence (tests/fixes/roundtrip.py).
if(TARGET isolint)
  add_test(NAME fixes/roundtrip
           COMMAND ${ISO_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/fixes/roundtrip.py
                   --tool $<TARGET_FILE:isolint> --corpus ${PROJECT_SOURCE_DIR}/tests/fixes)
  set_tests_properties(fixes/roundtrip PROPERTIES LABELS fixes TIMEOUT 120)
endif()
