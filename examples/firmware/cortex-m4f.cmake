# CMake toolchain file for a Cortex-M4F with Debian's gcc-arm-none-eabi, no C library:
#   cmake -S examples/firmware -B build-fw --toolchain examples/firmware/cortex-m4f.cmake ...
# For a Cortex-M7 with a double-precision FPU, set DYNGEN_CPU_FLAGS to
# "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb".
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
# no C library to link a test program against while CMake checks the compiler
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(DYNGEN_CPU_FLAGS "-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -mthumb"
    CACHE STRING "the core's code generation flags")
# -ffp-contract=off and no -ffast-math: the generated code's bits are the runtime's
set(CMAKE_C_FLAGS_INIT "${DYNGEN_CPU_FLAGS} -ffp-contract=off -ffreestanding")
set(CMAKE_CXX_FLAGS_INIT
    "${DYNGEN_CPU_FLAGS} -ffp-contract=off -ffreestanding -fno-exceptions -fno-rtti")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${DYNGEN_CPU_FLAGS} -nostdlib")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
