# Runs dyngen for one test package at build time: dyngen ${ARGS}. Its messages, the test robots'
# known warnings among them, go to LOG instead of the build's output, so that a passing build
# shows only what is new; when dyngen fails they are printed.
execute_process(COMMAND ${DYNGEN} ${ARGS} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
file(WRITE ${LOG} "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dyngen ${ARGS} failed (exit status ${rc}):\n${out}")
endif()
