# iso_set_warnings(target): the one place where compiler warnings are set.
function(iso_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wimplicit-fallthrough)
  if(ISO_WERROR)
    # GCC 12 reports false positives for std::string inside the standard library at -O3.
    target_compile_options(${target} PRIVATE -Werror -Wno-error=restrict -Wno-error=maybe-uninitialized
                                             -Wno-error=array-bounds -Wno-error=stringop-overflow)
  endif()
endfunction()
