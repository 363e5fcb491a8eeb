# Golden tests of isosim; included from tests/CMakeLists.txt after golden.cmake (whose
# iso_add_golden_suite and iso_add_help_golden it uses):
#   golden/isosim/<case>   tests/golden/isosim/<case>.{mpf|args|out|rc|stderr}: traces (CSV/JSON on
#                          stdout), summaries, every exit code; sample-* pin the cycle time of
#                          every sample (and its machine files / entries)
#   golden/help/isosim     tests/golden/help/isosim.txt: isosim --help (keep man/isosim.1 in step)
#   golden/man/isosim      man/isosim.1 is silent under groff -man -ww -z and names every option
# ISO_UPDATE_GOLDEN=1 ctest -R golden/isosim rebases the expectations.
if(TARGET isosim AND COMMAND iso_add_golden_suite)
  iso_add_golden_suite(isosim)
  iso_add_help_golden(isosim)
  add_test(NAME golden/man/isosim
           COMMAND ${CMAKE_COMMAND} -DMAN=${PROJECT_SOURCE_DIR}/man/isosim.1
                   -DHELP=${CMAKE_CURRENT_LIST_DIR}/help/isosim.txt
                   -P ${CMAKE_CURRENT_LIST_DIR}/isosim/CheckMan.cmake)
  set_tests_properties(golden/man/isosim PROPERTIES LABELS golden TIMEOUT 60)
endif()
