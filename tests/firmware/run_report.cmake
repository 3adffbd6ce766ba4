# Runs `dyngen firmware-report ${ARGS} -o WORK` and checks its firmware-report.json: the outputs
# of every function on the Cortex-M under qemu equal the host's bit for bit, nothing of a C
# library, libm or (in float) software double is linked, and each function's measured stack is
# within [bound / 1.5, bound] of the banner's bound; firmware-report exits 3 when one of these
# fails, and the JSON is read here too, so that a report that measured nothing fails as well.
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${DYNGEN} firmware-report ${ARGS} -o ${WORK} --quiet
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dyngen firmware-report ${ARGS}: exit ${rc}\n${out}")
endif()
file(READ ${WORK}/firmware-report.json report)
string(JSON equal GET "${report}" bits_equal)
string(JSON forbidden LENGTH "${report}" forbidden_symbols)
string(JSON functions LENGTH "${report}" functions)
if(NOT equal OR NOT forbidden EQUAL 0 OR functions EQUAL 0)
  message(FATAL_ERROR "firmware-report.json: bits_equal ${equal}, ${forbidden} forbidden symbols, "
                      "${functions} functions")
endif()
math(EXPR last "${functions} - 1")
foreach(k RANGE ${last})
  string(JSON name GET "${report}" functions ${k} name)
  string(JSON bound GET "${report}" functions ${k} stack_bound)
  string(JSON measured GET "${report}" functions ${k} stack_measured)
  string(JSON instructions GET "${report}" functions ${k} instructions)
  if(measured LESS_EQUAL 0 OR measured GREATER bound OR instructions LESS_EQUAL 0)
    message(FATAL_ERROR "${name}: stack ${measured} of bound ${bound}, ${instructions} instructions")
  endif()
  math(EXPR scaled "2 * ${bound}")
  math(EXPR limit "3 * ${measured}")
  if(scaled GREATER limit)
    message(FATAL_ERROR "${name}: bound ${bound} is more than 1.5 times the ${measured} measured")
  endif()
  message(STATUS "${name}: stack ${measured} of bound ${bound}, ${instructions} instructions")
endforeach()
