# cmake -DNM=nm -DLIBRARY=lib.a -DFORBIDDEN=regex -P check_undefined_symbols.cmake
# Fails when LIBRARY refers to (calls, but does not define) a symbol matching FORBIDDEN.
foreach(var NM LIBRARY FORBIDDEN)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_undefined_symbols.cmake: ${var} is not set")
  endif()
endforeach()
execute_process(COMMAND ${NM} --demangle --undefined-only ${LIBRARY}
                OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${LIBRARY}")
endif()
string(REGEX MATCHALL "[^\n]*(${FORBIDDEN})[^\n]*" found "${symbols}")
if(found)
  list(JOIN found "\n" lines)
  message(FATAL_ERROR "${LIBRARY} calls what it must not (${FORBIDDEN}):\n${lines}")
endif()
message(STATUS "${LIBRARY}: no undefined symbol matches ${FORBIDDEN}")
