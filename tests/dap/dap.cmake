# dap.cmake: isosim --dap as a process, included by tests/CMakeLists.txt.
#   dap/<case>  tests/dap/dap_session_tests.py, one test per function case_<case>: every sample
#               stepped through, pause, terminate, malformed messages, refused breakpoints,
#               the README's nvim-dap snippet (skipped, 77, without nvim).
# (The DebugClient tests of VS Code's adapter test client are editors/vscode-debugger.)
set(_iso_dap_script ${CMAKE_CURRENT_LIST_DIR}/dap_session_tests.py)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_iso_dap_script})
if(TARGET isosim)
  file(STRINGS ${_iso_dap_script} _iso_dap_defs REGEX "^def case_[a-z0-9_]+\\(")
  foreach(_def IN LISTS _iso_dap_defs)
    string(REGEX REPLACE "^def case_([a-z0-9_]+)\\(.*$" "\\1" _case "${_def}")
    add_test(NAME dap/${_case}
             COMMAND ${ISO_TEST_PYTHON} ${_iso_dap_script} ${_case} --isosim $<TARGET_FILE:isosim>
                     --samples ${PROJECT_SOURCE_DIR}/samples)
    set_tests_properties(dap/${_case} PROPERTIES LABELS dap TIMEOUT 120 SKIP_RETURN_CODE 77)
  endforeach()
endif()
