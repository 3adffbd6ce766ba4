# The interpreter for the Python module's tests (tests/python) and its fuzz target (tests/fuzz).
option(DYNGEN_PYTHON_TESTS "Test the generated Python module (pybind11-dev, python3-numpy, \
python3-pytest, python3-matplotlib, python3-pip, python3-torch)" ON)

# dyngen_test_python(VAR IMPORTS): VAR is the first python3 that can `import IMPORTS` ("numpy,
# pytest"), PATH's then the system's (a PATH may lead to an interpreter of its own, such as
# pyenv's, without Debian's modules), or "" if none can.
function(dyngen_test_python var imports)
  find_program(path_python3 python3)
  set(${var} "" PARENT_SCOPE)
  foreach(candidate IN ITEMS ${path_python3} /usr/bin/python3)
    execute_process(COMMAND ${candidate} -c "import ${imports}"
                    RESULT_VARIABLE status OUTPUT_QUIET ERROR_QUIET)
    if(status EQUAL 0)
      set(${var} ${candidate} PARENT_SCOPE)
      return()
    endif()
  endforeach()
endfunction()
