// What a package costs on its processor before it is flashed: each function's code bytes and an
// upper bound of its stack, from compiling the package with the target's GCC (-fstack-usage's
// frames on -fcallgraph-info's call graph).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "emit.hpp"
#include "output.hpp"

namespace dyngen::gen {

/// How a package is compiled for one processor: GCC (the only compiler with -fcallgraph-info),
/// its flags, and nm.
struct Toolchain {
  std::vector<std::string> c, cxx, nm;  // the commands' words: compiler for C, for C++, and nm
  std::vector<std::string> flags;    // processor flags, both languages
  std::optional<long> libgcc_frame;  // the stack of a compiler library routine (software double)
};

/// host: cc, c++ and nm (or $CC, $CXX, split into words: "ccache g++"), the baseline instruction
/// set (DYNGEN_NO_DISPATCH), no library routine expected; a Cortex-M: arm-none-eabi-gcc with its
/// -mcpu, -mfpu and -mfloat-abi.
Toolchain toolchain(const std::string& target);

/// The flags code in dialect's language is compiled with for the toolchain's processor: its
/// processor flags, -O2, the floating-point semantics of the bit-for-bit contract and the
/// language's flags (C++: no exceptions and no RTTI).
std::vector<std::string> compile_flags(const Toolchain& toolchain, const Dialect& dialect);

struct FunctionFootprint {
  std::string algorithm;
  long code_bytes = 0;                   // f, f_trig, their shared functions and tables
  std::optional<long> stack_bound;       // f(q, ...): its deepest call chain, empty if unbounded
  std::optional<long> trig_stack_bound;  // f_trig(q, trig, ...)
};

struct Footprint {
  std::string compiler;             // "arm-none-eabi-gcc 12.2.1 -O2 -mcpu=cortex-m4 ..."
  std::vector<FunctionFootprint> functions;
  long common_code_bytes = 0;       // joint_trig, sin and cos, kernels: shared by the functions
};

/// Compiles the package's source in dialect (its _dynamics.c or .cpp, among `files`) with the
/// toolchain at -O2 in a scratch directory, and measures each of `algorithms`. Throws InputError
/// when the compiler is missing or fails.
Footprint measure_footprint(const std::vector<GeneratedFile>& files, const Dialect& dialect,
                            const std::vector<std::string>& algorithms, const Toolchain& toolchain);

/// The footprint as the banner records it.
std::string footprint_text(const Footprint& footprint);

}  // namespace dyngen::gen
