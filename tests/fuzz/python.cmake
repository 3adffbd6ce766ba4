# fuzz_python (fuzz_python.cpp and fuzz_python.py): the generated Python module's argument
# parsing, through an embedded interpreter, on a pendulum's module that dyngen generates here
# from tests/python/hostile_pendulum.urdf and that is linked in. Built, like tests/python, with
# DYNGEN_PYTHON_TESTS (on by default); the same replay and libFuzzer run as the other targets.
include(${PROJECT_SOURCE_DIR}/tests/python/test_python.cmake)
if(DYNGEN_PYTHON_TESTS)
  dyngen_test_python(Python3_EXECUTABLE numpy)
  find_package(Python3 COMPONENTS Interpreter Development.Embed)
  find_package(pybind11 CONFIG)
  if(NOT Python3_EXECUTABLE OR NOT Python3_Development.Embed_FOUND OR NOT pybind11_FOUND)
    message(FATAL_ERROR "The Python module's fuzz target needs python3 with NumPy and its "
            "development files, and pybind11: scripts/install_deps.sh python (Debian 12), or "
            "-DDYNGEN_PYTHON_TESTS=OFF")
  endif()
  set(package ${CMAKE_CURRENT_BINARY_DIR}/python_package)
  set(robot ${PROJECT_SOURCE_DIR}/tests/python/hostile_pendulum.urdf)
  set(module_sources ${package}/Scalar_python.cpp ${package}/Scalar_dynamics.cpp
                     ${package}/Scalar_batch.cpp)
  # dyngen built with the sanitizers: urdfdom's known leak suppressed, as in the fuzz runs
  add_custom_command(
    OUTPUT ${module_sources}
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${package}
    COMMAND ${CMAKE_COMMAND} -E env
            LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp
            $<TARGET_FILE:dyngen> ${robot}
            -o ${package} --name Scalar --python --quiet
            --algorithms rnea,crba,aba_derivatives,frame_placements
    DEPENDS dyngen ${robot}
    COMMENT "Generating the Python module of fuzz_python")
  # -O1: the argument parsing is what the target exercises, and the build is shorter
  set_source_files_properties(${module_sources} PROPERTIES COMPILE_OPTIONS -O1)
  add_library(fuzz_python_module OBJECT ${module_sources})
  target_include_directories(fuzz_python_module PUBLIC ${package})
  target_link_libraries(fuzz_python_module PUBLIC pybind11::embed)
  target_compile_definitions(fuzz_python_module
                             PUBLIC DYNGEN_FUZZ_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

  add_executable(fuzz_python_replay fuzz_python.cpp replay_main.cpp)
  target_link_libraries(fuzz_python_replay PRIVATE fuzz_python_module)
  add_test(NAME fuzz.python.corpus
           COMMAND fuzz_python_replay ${CMAKE_CURRENT_SOURCE_DIR}/corpus/python)
  if(DYNGEN_BUILD_FUZZ)
    add_executable(fuzz_python fuzz_python.cpp)
    target_compile_options(fuzz_python PRIVATE -fsanitize=fuzzer)
    target_link_options(fuzz_python PRIVATE -fsanitize=fuzzer)
    target_link_libraries(fuzz_python PRIVATE fuzz_python_module)
    set(scratch ${CMAKE_CURRENT_BINARY_DIR}/corpus_python)
    file(MAKE_DIRECTORY ${scratch})
    # the leak check at exit only (README.md)
    add_test(NAME fuzz.python.run
             COMMAND fuzz_python -max_total_time=${DYNGEN_FUZZ_SECONDS} -timeout=20
                     -rss_limit_mb=4096 -print_final_stats=1 -detect_leaks=0 ${scratch}
                     ${CMAKE_CURRENT_SOURCE_DIR}/corpus/python)
    set_tests_properties(fuzz.python.run PROPERTIES TIMEOUT 600)
  endif()
endif()
