# Golden tests of isocc and of the image format; included from tests/CMakeLists.txt.
#   golden/isocc/<set>.dis   the listing of each sample set        (tests/golden/isocc/<set>.dis)
#   golden/isocc/<set>.hex   the annotated bytes of each sample set (tests/golden/isocc/<set>.hex)
#   golden/images/<fixture>  a hand-commented hex image rejected (or, good-*, accepted) by
#                            `isocc --verify` with the reason in tests/golden/images/<fixture>.stderr
#   golden/isocc/determinism the same bytes from any path order, spelling or working directory
# ISO_UPDATE_GOLDEN=1 ctest -R golden/isocc rebases the expectations.
add_executable(iso_hex2img ${CMAKE_CURRENT_LIST_DIR}/images/hex2img.cpp)
target_link_libraries(iso_hex2img PRIVATE iso::image)
iso_set_warnings(iso_hex2img)

get_filename_component(_isocc_root ${CMAKE_CURRENT_LIST_DIR}/../.. ABSOLUTE)
set(_isocc_run ${CMAKE_CURRENT_LIST_DIR}/isocc/RunIsocc.cmake)
set(_isocc_work ${CMAKE_CURRENT_BINARY_DIR}/golden-isocc)

file(GLOB _isocc_sets LIST_DIRECTORIES true CONFIGURE_DEPENDS ${_isocc_root}/samples/*)
foreach(_dir ${_isocc_sets})
  if(NOT IS_DIRECTORY ${_dir})
    continue()
  endif()
  get_filename_component(_set ${_dir} NAME)
  foreach(_mode dis hex)
    add_test(NAME golden/isocc/${_set}.${_mode}
             COMMAND ${CMAKE_COMMAND} -DMODE=${_mode} -DISOCC=$<TARGET_FILE:isocc> -DINPUT=${_dir}
                     -DEXPECTED=${CMAKE_CURRENT_LIST_DIR}/isocc/${_set}.${_mode} -DWORK=${_isocc_work}
                     -DNAME=${_set}-${_mode} -P ${_isocc_run})
  endforeach()
endforeach()

file(GLOB _isocc_fixtures CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/images/*.hex)
foreach(_hex ${_isocc_fixtures})
  get_filename_component(_name ${_hex} NAME_WE)
  add_test(NAME golden/images/${_name}
           COMMAND ${CMAKE_COMMAND} -DMODE=verify -DISOCC=$<TARGET_FILE:isocc> -DHEX2IMG=$<TARGET_FILE:iso_hex2img>
                   -DINPUT=${_hex} -DEXPECTED=${CMAKE_CURRENT_LIST_DIR}/images/${_name}.stderr
                   -DWORK=${_isocc_work}/images -DNAME=${_name} -P ${_isocc_run})
endforeach()

add_test(NAME golden/isocc/determinism
         COMMAND ${CMAKE_COMMAND} -DMODE=determinism -DISOCC=$<TARGET_FILE:isocc> -DSOURCE_DIR=${_isocc_root}
                 -DSETS=drilling_when,semi_auto,pallet_loader -DWORK=${_isocc_work}/determinism
                 -P ${_isocc_run})
