# ctest -P script: generates NAME's package with --python (dyngen DYNGEN, robot INPUT, OPTIONS),
# builds it with its own CMakeLists.txt for PYTHON, runs test_module.py (in TESTS) with pytest on
# its module and, if OPTIONS has --torch, test_torch.py on NAME_torch.py; given EXAMPLES (the
# examples/ directory), runs python/rollouts.py on the module and, with --torch, the two
# examples of torch/ (ur5's); given CONTACTS (--contacts), test_contacts.py. SCRATCH is
# rewritten; OPTIMIZE, if set, replaces the package's Release flags' -O3.
cmake_policy(SET CMP0057 NEW)
file(REMOVE_RECURSE ${SCRATCH})
string(TOUPPER ${NAME} upper)
set(source ${SCRATCH}/package)
set(binary ${SCRATCH}/build)
foreach(step IN ITEMS generate configure build pytest example identification optimisation)
  if(step STREQUAL "generate")
    set(cmd ${DYNGEN} ${INPUT} -o ${source} --name ${NAME} --quiet --python ${OPTIONS})
    if(CONTACTS)
      list(APPEND cmd --contacts ${CONTACTS})
    endif()
  elseif(step STREQUAL "configure")
    set(cmd ${CMAKE_COMMAND} -S ${source} -B ${binary} -D${upper}_BUILD_CHECK=OFF
            -DPython3_EXECUTABLE=${PYTHON})
    if(OPTIMIZE)
      list(APPEND cmd "-DCMAKE_CXX_FLAGS_RELEASE=${OPTIMIZE} -DNDEBUG")
    endif()
  elseif(step STREQUAL "build")
    set(cmd ${CMAKE_COMMAND} --build ${binary} --parallel 2)
  elseif(step STREQUAL "pytest")
    string(REPLACE ";" " " model_options "${MODEL_OPTIONS}")
    set(tests ${TESTS}/test_module.py)
    if("--torch" IN_LIST OPTIONS)
      list(APPEND tests ${TESTS}/test_torch.py)
    endif()
    if(CONTACTS)
      list(APPEND tests ${TESTS}/test_contacts.py)
    endif()
    set(cmd ${CMAKE_COMMAND} -E env PYTHONPATH=${binary} DYNGEN_MODULE=${NAME}_dynamics
            DYNGEN=${DYNGEN} DYNGEN_ROBOT=${INPUT} "DYNGEN_ROBOT_OPTIONS=${model_options}"
            DYNGEN_CONTACTS=${CONTACTS}
            MPLBACKEND=Agg ${PYTHON} -m pytest -q -p no:cacheprovider ${tests})
  elseif(step STREQUAL "example" AND EXAMPLES)
    set(cmd ${CMAKE_COMMAND} -E env PYTHONPATH=${binary} ${PYTHON} ${EXAMPLES}/python/rollouts.py
            ${NAME}_dynamics --rollouts 32 --seconds 0.2 --plot ${SCRATCH}/energy.png)
  elseif(step STREQUAL "identification" AND EXAMPLES AND "--torch" IN_LIST OPTIONS)
    set(cmd ${CMAKE_COMMAND} -E env PYTHONPATH=${binary} ${PYTHON}
            ${EXAMPLES}/torch/system_identification.py ${NAME} --urdf ${INPUT} --dyngen ${DYNGEN})
  elseif(step STREQUAL "optimisation" AND EXAMPLES AND "--torch" IN_LIST OPTIONS)
    set(cmd ${CMAKE_COMMAND} -E env PYTHONPATH=${binary} MPLBACKEND=Agg ${PYTHON}
            ${EXAMPLES}/torch/trajectory_optimisation.py ${NAME} --plot ${SCRATCH}/reach.png)
  else()
    continue()
  endif()
  execute_process(COMMAND ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed:\n${out}")
  endif()
  message(STATUS "${step}:\n${out}")
endforeach()
foreach(plot IN ITEMS energy reach)
  if(EXAMPLES AND (plot STREQUAL "energy" OR "--torch" IN_LIST OPTIONS) AND NOT EXISTS ${SCRATCH}/${plot}.png)
    message(FATAL_ERROR "the example wrote no ${plot}.png")
  endif()
endforeach()
