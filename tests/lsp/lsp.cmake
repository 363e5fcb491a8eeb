# lsp.cmake: the language server against a real client, included by tests/CMakeLists.txt.
#   lsp/neovim   headless Neovim (0.7+) drives `isolint --lsp` (tests/lsp/nvim_client.lua);
#                skipped (77) when nvim is not installed.
if(TARGET isolint)
  add_test(NAME lsp/neovim
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_client.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim)
  set_tests_properties(lsp/neovim PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp)
endif()
# lsp/neovim-format  the same client formats a buffer (tests/lsp/nvim_format.lua): the buffer
#                    then equals what isofmt prints for the file; skipped (77) without nvim.
if(TARGET isolint AND TARGET isofmt)
  add_test(NAME lsp/neovim-format
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_format.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim-format)
  set_tests_properties(lsp/neovim-format PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp
                       ENVIRONMENT "ISOFMT=$<TARGET_FILE:isofmt>")
endif()
# lsp/readme-neovim  the Neovim snippet of README.md, run as it is (tests/lsp/readme_nvim.sh)
if(TARGET isolint)
  add_test(NAME lsp/readme-neovim
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/readme_nvim.sh $<TARGET_FILE:isolint>
                   ${PROJECT_SOURCE_DIR}/README.md ${CMAKE_CURRENT_BINARY_DIR}/lsp-readme)
  set_tests_properties(lsp/readme-neovim PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp)
endif()
# lsp/<case>  isolint --lsp as a process (tests/lsp/lsp_session_tests.py, one test per
#             function case_<case>): how it ends, what it refuses without ending.
set(_iso_lsp_script ${CMAKE_CURRENT_LIST_DIR}/lsp_session_tests.py)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_iso_lsp_script})
if(TARGET isolint)
  file(STRINGS ${_iso_lsp_script} _iso_lsp_defs REGEX "^def case_[a-z0-9_]+\\(")
  foreach(_def IN LISTS _iso_lsp_defs)
    string(REGEX REPLACE "^def case_([a-z0-9_]+)\\(.*$" "\\1" _case "${_def}")
    add_test(NAME lsp/${_case} COMMAND ${ISO_TEST_PYTHON} ${_iso_lsp_script} ${_case} --isolint $<TARGET_FILE:isolint>)
    set_tests_properties(lsp/${_case} PROPERTIES LABELS lsp TIMEOUT 60)
  endforeach()
endif()
# lsp/neovim-policy  the editor applies the command line's policy (tests/lsp/nvim_policy.lua):
#                    settings file, machine file, dialect, disable list and per-path overrides.
if(TARGET isolint)
  add_test(NAME lsp/neovim-policy
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_policy.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim-policy)
  set_tests_properties(lsp/neovim-policy PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp
                       ENVIRONMENT "ISO_SAMPLES=${PROJECT_SOURCE_DIR}/samples")
endif()
# lsp/neovim-cycletime  the cycle time in Neovim (tests/lsp/nvim_cycletime.lua): the code lens
#                       of a sample's dry run, inlay hints, the hover's line time, folding ranges
#                       and semantic tokens; skipped (77) without nvim.
if(TARGET isolint AND TARGET isosim)
  add_test(NAME lsp/neovim-cycletime
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_cycletime.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim-cycletime)
  set_tests_properties(lsp/neovim-cycletime PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 40 LABELS lsp
                       ENVIRONMENT "ISO_SAMPLES=${PROJECT_SOURCE_DIR}/samples;ISOSIM=$<TARGET_FILE:isosim>")
endif()
