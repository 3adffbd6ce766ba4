# The generated check must fail when both sides return NaN: equal NaN bits prove nothing.
# Generates RNEA for INPUT into SCRATCH/src, makes the runtime's model compute NaN (its gravity)
# and the generated rnea add NaN to every output, then builds the package's check and expects it to fail
# on a non-finite output.
file(REMOVE_RECURSE ${SCRATCH})
set(src ${SCRATCH}/src)
execute_process(COMMAND ${DYNGEN} ${INPUT} -o ${src} --name nan_probe --algorithms rnea --quiet
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dyngen failed (${rc}): ${err}")
endif()

file(READ ${src}/nan_probe_model.hpp model)
string(REGEX REPLACE "model_gravity\\[3\\] = {[^}]*}"
       "model_gravity[3] = {__builtin_nan(\"\"), 0.0, 0.0}" nan_model "${model}")
file(READ ${src}/nan_probe_dynamics.cpp code)
string(REGEX REPLACE "\n    tau\\[([0-9]+)\\] = ([^;]+);" "\n    tau[\\1] = \\2 + __builtin_nan(\"\");"
       nan_code "${code}")
if(nan_model STREQUAL model OR nan_code STREQUAL code)
  message(FATAL_ERROR "the probe found no gravity or no tau store to replace")
endif()
file(WRITE ${src}/nan_probe_model.hpp "${nan_model}")
file(WRITE ${src}/nan_probe_dynamics.cpp "${nan_code}")

set(build ${SCRATCH}/build)
execute_process(COMMAND ${CMAKE_COMMAND} -S ${src} -B ${build} -Ddyngen_DIR=${dyngen_DIR}
                        -DNAN_PROBE_BUILD_CHECK=ON
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${build}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the probe package did not build:\n${out}")
endif()
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${build} --output-on-failure
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "the check passed with NaN on both sides:\n${out}")
endif()
if(NOT out MATCHES "rnea: tau\\[0\\] differs or is not finite")
  message(FATAL_ERROR "the check failed, but not on the NaN output:\n${out}")
endif()
message(STATUS "the check failed on NaN, as it must")
