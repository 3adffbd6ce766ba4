# A generated source (SOURCE, with its package's headers beside it) compiled by COMPILER with
# -ffast-math, and again with -Ofast, must stop at its own #error, which names the file and says
# why (floating_point.in): fast-math would silently break equality with the runtime.
get_filename_component(dir ${SOURCE} DIRECTORY)
get_filename_component(file ${SOURCE} NAME)
foreach(flag -ffast-math -Ofast)
  execute_process(COMMAND ${COMPILER} ${flag} -I${dir} -c ${SOURCE} -o ${OBJECT}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc EQUAL 0 OR NOT out MATCHES "${file}: -ffast-math or -Ofast breaks equality with the runtime")
    message(FATAL_ERROR "${COMPILER} ${flag} ${file}: not refused by its #error (exit status ${rc}):\n${out}")
  endif()
endforeach()
message(STATUS "${file}: refused under -ffast-math and -Ofast")
