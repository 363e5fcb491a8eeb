# lsp.cmake: the language server against a real client, included by tests/CMakeLists.txt.
#   lsp/neovim   headless Neovim (0.7+) drives `isolint --lsp` (tests/lsp/nvim_client.lua);
#                skipped (77) when nvim is not installed.
if(TARGET isolint)
  add_test(NAME lsp/neovim
           COMMAND /bin/sh ${CMAKE_CURRENT_LIST_DIR}/run_nvim.sh $<TARGET_FILE:isolint>
                   ${CMAKE_CURRENT_LIST_DIR}/nvim_client.lua ${CMAKE_CURRENT_BINARY_DIR}/lsp-neovim)
  set_tests_properties(lsp/neovim PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 30 LABELS lsp)
endif()
