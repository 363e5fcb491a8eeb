# IsoInstall.cmake: what `cmake --install` puts under the prefix (GNUInstallDirs):
#   bin/                                        isolint, isocc, isosim, isofmt
#   share/man/man1, man5, man7                  man/*.1, *.5, *.7
#   share/bash-completion/completions/TOOL      bash completion
#   share/zsh/site-functions/_TOOL              zsh completion
#   share/fish/vendor_completions.d/TOOL.fish   fish completion
# The completions are not written by hand: each tool prints them from its own CLI11 definition
# (TOOL --completion SHELL, lib/driver/ShellCompletion.cpp), at build time into
# ${PROJECT_BINARY_DIR}/completions/, and those files are installed.
include(GNUInstallDirs)

set(ISO_TOOLS isolint isocc isosim isofmt)
install(TARGETS ${ISO_TOOLS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

foreach(section 1 5 7)
  file(GLOB _iso_pages CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/man/*.${section})
  install(FILES ${_iso_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man${section})
endforeach()

set(ISO_COMPLETIONS_DIR ${PROJECT_BINARY_DIR}/completions)
set(_iso_completion_files "")
foreach(tool IN LISTS ISO_TOOLS)
  foreach(shell bash zsh fish)
    if(shell STREQUAL "bash")
      set(_file ${ISO_COMPLETIONS_DIR}/bash/${tool})
      set(_dest ${CMAKE_INSTALL_DATADIR}/bash-completion/completions)
    elseif(shell STREQUAL "zsh")
      set(_file ${ISO_COMPLETIONS_DIR}/zsh/_${tool})
      set(_dest ${CMAKE_INSTALL_DATADIR}/zsh/site-functions)
    else()
      set(_file ${ISO_COMPLETIONS_DIR}/fish/${tool}.fish)
      set(_dest ${CMAKE_INSTALL_DATADIR}/fish/vendor_completions.d)
    endif()
    add_custom_command(OUTPUT ${_file}
                       COMMAND ${CMAKE_COMMAND} -E make_directory ${ISO_COMPLETIONS_DIR}/${shell}
                       COMMAND ${CMAKE_COMMAND} -DTOOL=$<TARGET_FILE:${tool}> -DSHELL=${shell} -DOUT=${_file}
                               -P ${PROJECT_SOURCE_DIR}/cmake/RunCompletion.cmake
                       DEPENDS ${tool} ${PROJECT_SOURCE_DIR}/cmake/RunCompletion.cmake
                       COMMENT "Generating the ${shell} completion of ${tool}"
                       VERBATIM)
    list(APPEND _iso_completion_files ${_file})
    install(FILES ${_file} DESTINATION ${_dest})
  endforeach()
endforeach()
add_custom_target(completions ALL DEPENDS ${_iso_completion_files})
