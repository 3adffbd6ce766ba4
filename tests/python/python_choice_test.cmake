# ctest -P script: a --python package (dyngen DYNGEN, robot INPUT) configured where the first
# python3 on PATH cannot import NumPy (a wrapper that runs PYTHON without its site packages)
# must take an interpreter that can (PYTHON's /usr/bin/python3), and, told to use the wrapper
# (-DPython3_EXECUTABLE), must stop at configure time naming it and NumPy. SCRATCH is rewritten.
file(REMOVE_RECURSE ${SCRATCH})
file(MAKE_DIRECTORY ${SCRATCH}/bin)
file(WRITE ${SCRATCH}/bin/python3 "#!/bin/sh\nexec ${PYTHON} -S \"$@\"\n")
file(CHMOD ${SCRATCH}/bin/python3 PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
execute_process(COMMAND ${SCRATCH}/bin/python3 -c "import numpy" RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_QUIET)
if(rc EQUAL 0)
  message(FATAL_ERROR "the wrapper imports numpy: the test would not test anything")
endif()
execute_process(COMMAND ${DYNGEN} ${INPUT} -o ${SCRATCH}/package --name chosen --quiet --python
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "generate failed:\n${out}")
endif()

# the wrapper first on PATH: the configure step passes over it
execute_process(COMMAND ${CMAKE_COMMAND} -E env "PATH=${SCRATCH}/bin:$ENV{PATH}"
                        ${CMAKE_COMMAND} -S ${SCRATCH}/package -B ${SCRATCH}/found
                        -DCHOSEN_BUILD_CHECK=OFF
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configure with the wrapper first on PATH failed:\n${out}")
endif()
file(STRINGS ${SCRATCH}/found/CMakeCache.txt chosen REGEX "^Python3_EXECUTABLE:")
if(NOT chosen STREQUAL "Python3_EXECUTABLE:FILEPATH=/usr/bin/python3")
  message(FATAL_ERROR "took ${chosen}, not /usr/bin/python3")
endif()

# the wrapper asked for: a configure error that names it and NumPy
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SCRATCH}/package -B ${SCRATCH}/refused
                        -DCHOSEN_BUILD_CHECK=OFF -DPython3_EXECUTABLE=${SCRATCH}/bin/python3
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "configure took an interpreter without NumPy:\n${out}")
endif()
string(REGEX REPLACE "[ \n]+" " " flat "${out}")  # CMake wraps and indents the message
foreach(expected "${SCRATCH}/bin/python3" "cannot import numpy" "python3-numpy")
  string(FIND "${flat}" "${expected}" at)
  if(at LESS 0)
    message(FATAL_ERROR "the configure error does not say '${expected}':\n${out}")
  endif()
endforeach()
message(STATUS "passed over the wrapper, and refused it when asked for")
