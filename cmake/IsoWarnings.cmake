# iso_set_warnings(target): the one place where compiler warnings are set.
function(iso_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wimplicit-fallthrough)
  if(ISO_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
    if(ISO_SANITIZE OR ISO_FUZZ)
      # Instrumented builds make GCC 12 report false positives inside the standard library.
      target_compile_options(${target} PRIVATE -Wno-error=restrict -Wno-error=maybe-uninitialized
                                               -Wno-error=array-bounds -Wno-error=stringop-overflow)
    endif()
  endif()
endfunction()
