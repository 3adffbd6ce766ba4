# A generated package's own CMakeLists.txt (in SOURCE) under the names it derives from the
# robot's (NAME: its prefix): configured in BINARY with NAME_ISA=avx2 and NAME_BUILD_CHECK=OFF,
# it must build the library with -mavx2 and without the check (the test project builds that);
# configured again with an instruction set it does not know, it must stop with a message that
# names the option. The banner's "message(FATAL_ERROR injected)" must stay a comment throughout.
file(REMOVE_RECURSE ${BINARY})
string(TOUPPER ${NAME} upper)
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -D${upper}_ISA=avx2
                        -D${upper}_BUILD_CHECK=OFF
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} --verbose
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the package did not configure and build:\n${out}")
endif()
if(NOT out MATCHES "-mavx2")
  message(FATAL_ERROR "${upper}_ISA=avx2 did not reach the compiler:\n${out}")
endif()
if(out MATCHES "-Werror" OR NOT out MATCHES "-Wextra")
  message(FATAL_ERROR "by default the library must build with warnings, not errors:\n${out}")
endif()
if(NOT EXISTS ${BINARY}/lib${NAME}_dynamics.a)
  message(FATAL_ERROR "no lib${NAME}_dynamics.a in ${BINARY}:\n${out}")
endif()
file(GLOB check ${BINARY}/${NAME}_check*)
if(check)
  message(FATAL_ERROR "${upper}_BUILD_CHECK=OFF, yet the check was built: ${check}")
endif()

execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -D${upper}_WERROR=ON
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} --verbose
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
endif()
if(NOT rc EQUAL 0 OR NOT out MATCHES "-Werror")
  message(FATAL_ERROR "${upper}_WERROR=ON did not build with -Werror (exit status ${rc}):\n${out}")
endif()

execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -D${upper}_ISA=sse3
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
string(REGEX REPLACE "[ \n]+" " " flat "${out}")  # CMake wraps its messages
if(rc EQUAL 0 OR NOT flat MATCHES "${upper}_ISA is 'sse3': give dispatch, sse2, avx2 or avx512")
  message(FATAL_ERROR "${upper}_ISA=sse3 was not refused by name (exit status ${rc}):\n${out}")
endif()
message(STATUS "${NAME}: built with ${upper}_ISA=avx2, with ${upper}_WERROR=ON, refused "
               "${upper}_ISA=sse3")
