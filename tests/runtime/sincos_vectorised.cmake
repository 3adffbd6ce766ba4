# ctest -P script: the array forms of sin and cos (sincos.h), compiled as a generated package is
# (-O3 -ffp-contract=off), must have their loop vectorised: joint_trig's speed rests on it, and
# one 64-bit integer comparison in the double loop once stopped GCC from vectorising it
# unnoticed. Each form is compiled alone, so that a vectorised loop reported is its own.
# Takes COMPILER, INCLUDE and SCRATCH.
foreach(form "double|dyngen_sincos_array" "float|dyngen_sincosf_array")
  string(REPLACE "|" ";" form "${form}")
  list(GET form 0 type)
  list(GET form 1 function)
  set(source ${SCRATCH}/sincos_vectorised_${type}.c)
  file(WRITE ${source} "#include \"dyngen/sincos.h\"\n"
                       "void f(const ${type}* x, ${type}* s, ${type}* c, int n) {\n"
                       "  ${function}(x, s, c, n);\n}\n")
  execute_process(
    COMMAND ${COMPILER} -x c -O3 -ffp-contract=off -fopt-info-vec-optimized -I ${INCLUDE} -c
            ${source} -o ${source}.o
    RESULT_VARIABLE status ERROR_VARIABLE report OUTPUT_VARIABLE out)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "compiling ${function} failed:\n${report}")
  endif()
  if(NOT report MATCHES "sincos.h:[0-9]+:[0-9]+: optimized: loop vectorized")
    message(FATAL_ERROR "${function}'s loop is not vectorised; GCC says:\n${report}")
  endif()
  message(STATUS "${function}: vectorised")
endforeach()
