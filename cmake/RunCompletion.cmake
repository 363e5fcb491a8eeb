# cmake -DTOOL=<binary> -DSHELL=bash|zsh|fish -DOUT=<file> -P RunCompletion.cmake
# Writes the completion script that `TOOL --completion SHELL` prints to OUT; fails if it fails.
execute_process(COMMAND ${TOOL} --completion ${SHELL}
                OUTPUT_FILE ${OUT}.tmp
                ERROR_VARIABLE err
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(REMOVE ${OUT}.tmp)
  message(FATAL_ERROR "${TOOL} --completion ${SHELL} failed (${rc}): ${err}")
endif()
file(RENAME ${OUT}.tmp ${OUT})
