# A package's check on an emulated processor: under QEMU with -cpu CPU, PROBE must see AVX2 as
# AVX2 says (1 or 0: so the loader binds that clone), and the package's CHECK, bit for bit
# against the runtime, must pass its tests that match FILTER (--gtest_filter: emulated, the
# whole check takes half a minute). With LIBRARY, one binary's path through DYNGEN_DISPATCH:
# the library (nm is NM) must hold AVX2 and baseline clones.
if(LIBRARY)
  execute_process(COMMAND ${NM} -C ${LIBRARY} RESULT_VARIABLE rc OUTPUT_VARIABLE symbols)
  foreach(clone avx2 default)
    if(NOT rc EQUAL 0 OR NOT symbols MATCHES "\\[clone \\.${clone}\\]")
      message(FATAL_ERROR "${LIBRARY} holds no ${clone} clone (nm exit status ${rc})")
    endif()
  endforeach()
endif()
execute_process(COMMAND ${QEMU} -cpu ${CPU} ${PROBE} RESULT_VARIABLE rc OUTPUT_VARIABLE has_avx2
                ERROR_QUIET OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0 OR NOT has_avx2 STREQUAL AVX2)
  message(FATAL_ERROR "qemu -cpu ${CPU}: the probe says AVX2 '${has_avx2}' (exit status ${rc}), "
          "not ${AVX2}")
endif()
execute_process(COMMAND ${QEMU} -cpu ${CPU} ${CHECK} --gtest_filter=${FILTER}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "\\[  PASSED  \\] [1-9]")
  message(FATAL_ERROR "qemu -cpu ${CPU}: the check failed or ran no test of ${FILTER} "
          "(exit status ${rc}):\n${out}")
endif()
message(STATUS "qemu -cpu ${CPU} (AVX2 ${AVX2}): the check passed")
