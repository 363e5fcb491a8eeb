# Golden tests of isosim; included from tests/CMakeLists.txt after golden.cmake (whose
# iso_add_golden_suite and iso_add_help_golden it uses):
#   golden/isosim/<case>   tests/golden/isosim/<case>.{mpf|args|out|rc|stderr}: traces (CSV/JSON on
#                          stdout), summaries, every exit code; sample-* pin the cycle time of
#                          every sample (and its machine files / entries)
#   golden/help/isosim     tests/golden/help/isosim.txt: isosim --help (keep man/isosim.1 in step)
#   golden/man/isosim      man/isosim.1 is silent under groff -man -ww -z and names every option
#   plot/isosim/xml        isosim --plot on a sample: well-formed SVG, the moving axes only, units,
#                          legend, the tool path view, the same bytes twice (tests/golden/check_plot.py)
#   plot/isosim/render     the same, rendered to PNG by rsvg-convert (SKIP when it is not installed)
#   golden/isosim/sweep-parallel  isosim --sweep-jobs run by GNU parallel gives the cycle times of the
#                          --sweep table (tests/golden/check_sweep_parallel.py; SKIP without parallel)
# ISO_UPDATE_GOLDEN=1 ctest -R golden/isosim rebases the expectations.
if(TARGET isosim AND COMMAND iso_add_golden_suite)
  iso_add_golden_suite(isosim)
  iso_add_help_golden(isosim)
  add_test(NAME golden/man/isosim
           COMMAND ${CMAKE_COMMAND} -DMAN=${PROJECT_SOURCE_DIR}/man/isosim.1
                   -DHELP=${CMAKE_CURRENT_LIST_DIR}/help/isosim.txt
                   -P ${CMAKE_CURRENT_LIST_DIR}/isosim/CheckMan.cmake)
  set_tests_properties(golden/man/isosim PROPERTIES LABELS golden TIMEOUT 60)
  add_test(NAME plot/isosim/xml
           COMMAND ${ISO_TEST_PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_plot.py --tool $<TARGET_FILE:isosim>
                   --program ${PROJECT_SOURCE_DIR}/samples/five_axis/marcatura_5assi.mpf --moving XYZAC --rapids
                   --out-dir ${CMAKE_CURRENT_BINARY_DIR}/plot)
  add_test(NAME plot/isosim/render
           COMMAND ${ISO_TEST_PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_plot.py --tool $<TARGET_FILE:isosim>
                   --program ${PROJECT_SOURCE_DIR}/samples/pallet_loader/pallettizzatore.mpf --moving XYZ --rapids
                   --out-dir ${CMAKE_CURRENT_BINARY_DIR}/plot --render)
  set_tests_properties(plot/isosim/xml plot/isosim/render PROPERTIES LABELS plot TIMEOUT 120)
  set_tests_properties(plot/isosim/render PROPERTIES SKIP_RETURN_CODE 77)
  add_test(NAME golden/isosim/sweep-parallel
           COMMAND ${ISO_TEST_PYTHON} ${CMAKE_CURRENT_LIST_DIR}/check_sweep_parallel.py --tool $<TARGET_FILE:isosim>
                   --sweep sweeps/grid.toml --work-dir ${CMAKE_CURRENT_LIST_DIR}/isosim
                   --out-dir ${CMAKE_CURRENT_BINARY_DIR}/sweep)
  set_tests_properties(golden/isosim/sweep-parallel PROPERTIES LABELS golden TIMEOUT 120 SKIP_RETURN_CODE 77)
endif()
