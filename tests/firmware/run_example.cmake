# examples/firmware as its README says: generate ur5 in float for a Cortex-M4F with DYNGEN,
# configure and build the example with its toolchain file, run it under qemu; it exits 0 when
# the tracking error fell as computed-torque control makes it fall. WORK is a scratch directory.
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${ARGN}: exit ${rc}\n${out}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()
run(${DYNGEN} ${EXAMPLE}/../ur5.urdf -o ${WORK}/gen --scalar float --target cortex-m4f
    --algorithms crba,nle,aba --quiet)
run(${CMAKE_COMMAND} -S ${EXAMPLE} -B ${WORK}/build --toolchain ${EXAMPLE}/cortex-m4f.cmake
    -DDYNGEN_PACKAGE=${WORK}/gen)
run(${CMAKE_COMMAND} --build ${WORK}/build)
run(${QEMU} -machine mps2-an386 -nographic -monitor none -serial none
    -semihosting-config enable=on,target=native -kernel ${WORK}/build/control_loop.elf)
if(NOT out MATCHES "t = 1000 ms, largest joint error [0-9]+")
  message(FATAL_ERROR "the control loop did not run its second:\n${out}")
endif()
message(STATUS "${out}")
