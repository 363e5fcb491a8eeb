# lsp.cmake: the language server against a real client, included by tests/CMakeLists.txt.
#   lsp/neovim   headless Neovim (0.7+) drives `isolint --lsp` (tests/lsp/nvim_client.lua);
#                skipped (77) when nvim is not installed.
if(TARGET isolint)
  add_test(NAME lsp/neovim
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_client.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim)
  set_tests_properties(lsp/neovim PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp)
endif()
# lsp/readme-neovim  the Neovim snippet of README.md, run as it is (tests/lsp/readme_nvim.sh)
if(TARGET isolint)
  add_test(NAME lsp/readme-neovim
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/readme_nvim.sh $<TARGET_FILE:isolint>
                   ${PROJECT_SOURCE_DIR}/README.md ${CMAKE_CURRENT_BINARY_DIR}/lsp-readme)
  set_tests_properties(lsp/readme-neovim PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp)
endif()
