# Installs dyngen from DYNGEN_BUILD into INSTALL/prefix, moves it to INSTALL/moved, then
# configures, builds and tests a generated directory with its own CMakeLists.txt against the
# moved install, as a user would: cmake -S SOURCE -B BINARY -Ddyngen_DIR=... && cmake --build
# && ctest; with the package's warnings-as-errors option WERROR (UR5_WERROR) on, as dyngen's tests
# hold its code to that.
file(REMOVE_RECURSE ${BINARY} ${INSTALL})
set(dyngen_DIR ${INSTALL}/moved/lib/cmake/dyngen)
foreach(step IN ITEMS install move configure build test)
  if(step STREQUAL "install")
    set(cmd ${CMAKE_COMMAND} --install ${DYNGEN_BUILD} --prefix ${INSTALL}/prefix)
  elseif(step STREQUAL "move")
    set(cmd ${CMAKE_COMMAND} -E rename ${INSTALL}/prefix ${INSTALL}/moved)
  elseif(step STREQUAL "configure")
    set(cmd ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -Ddyngen_DIR=${dyngen_DIR}
            -D${WERROR}=ON)
  elseif(step STREQUAL "build")
    set(cmd ${CMAKE_COMMAND} --build ${BINARY})
  else()
    set(cmd ${CMAKE_CTEST_COMMAND} --test-dir ${BINARY} --output-on-failure)
  endif()
  execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed:\n${out}")
  endif()
endforeach()
# the check found the moved install, not this build tree
file(STRINGS ${BINARY}/CMakeCache.txt found REGEX "^dyngen_DIR:")
string(REGEX REPLACE "^dyngen_DIR:[A-Z]+=" "" found "${found}")
if(NOT found STREQUAL dyngen_DIR)
  message(FATAL_ERROR "the check used ${found}, not ${dyngen_DIR}")
endif()
message(STATUS "${out}")
