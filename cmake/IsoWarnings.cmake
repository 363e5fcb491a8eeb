# iso_set_warnings(target): the one place where compiler warnings are set.
function(iso_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wimplicit-fallthrough)
  if(ISO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
