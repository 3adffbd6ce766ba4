# Runs ELF under qemu-system-arm (MACHINE) with semihosting and compares its printout with HOST's,
# bit for bit; checks with NM that the image links nothing of a C library or libm (no malloc,
# no sin) and, for SCALAR float, no software double (__aeabi_d*); and checks each function's
# stack, measured by the harness, against the bound that the banner of SOURCE (the package's
# code, generated with --target) records: never below, at most 1.5 times above.
execute_process(COMMAND ${NM} ${ELF} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} ${ELF} failed")
endif()
foreach(forbidden malloc free calloc realloc memset memcpy sin cos sinf cosf sqrt sqrtf)
  if(symbols MATCHES "[ \n]${forbidden}\n")
    message(FATAL_ERROR "${ELF} links ${forbidden}")
  endif()
endforeach()
if(SCALAR STREQUAL "float" AND symbols MATCHES "__aeabi_d[a-z0-9]+")
  message(FATAL_ERROR "${ELF} is float but links software double: ${CMAKE_MATCH_0}")
endif()

execute_process(
  COMMAND ${QEMU} -machine ${MACHINE} -nographic -monitor none -serial none
          -semihosting-config enable=on,target=native -kernel ${ELF}
  # qemu writes semihosting output to stdout or stderr depending on what they are: take both
  OUTPUT_VARIABLE target ERROR_VARIABLE target RESULT_VARIABLE rc TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${ELF} under ${MACHINE}: exit ${rc}\n${target}")
endif()
execute_process(COMMAND ${HOST} OUTPUT_VARIABLE host RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${HOST}: exit ${rc}")
endif()
string(REGEX MATCHALL "\n" lines "${host}")
list(LENGTH lines count)
if(count EQUAL 0)
  message(FATAL_ERROR "${HOST} printed nothing")
endif()
# the stack lines are the Cortex-M's alone
string(REGEX MATCHALL "stack [a-z_]+ [0-9]+\n" stack_lines "${target}")
string(REGEX REPLACE "stack [a-z_]+ [0-9]+\n" "" target "${target}")

file(READ ${SOURCE} source)
foreach(function rnea crba aba)
  if(NOT source MATCHES "\n//   ${function} +code +[0-9]+ +stack +([0-9]+) / [0-9]+\n")
    message(FATAL_ERROR "${SOURCE}'s banner records no stack bound for ${function}")
  endif()
  set(bound ${CMAKE_MATCH_1})
  if(NOT stack_lines MATCHES "stack ${function} ([0-9]+)")
    message(FATAL_ERROR "${MACHINE} did not report ${function}'s stack:\n${stack_lines}")
  endif()
  set(measured ${CMAKE_MATCH_1})
  if(measured EQUAL 0)
    message(FATAL_ERROR "${function}: no stack use measured")
  endif()
  math(EXPR percent "100 * ${bound} / ${measured}")
  message(STATUS "${function}: stack measured ${measured} bytes, bound ${bound} (${percent}%)")
  if(measured GREATER bound OR percent GREATER 150)
    message(FATAL_ERROR "${function}: ${measured} bytes of stack measured, bound ${bound}")
  endif()
endforeach()

if(NOT target STREQUAL host)
  message(FATAL_ERROR "${MACHINE} and the host differ.\n${MACHINE}:\n${target}\nhost:\n${host}")
endif()
message(STATUS "${MACHINE}: ${count} lines of outputs equal to the host's, bit for bit")
