// Schedules a traced program and prints it as C++ or C: live nodes in creation order (the
// algorithm's order), one operation per statement, grouped and labelled by body and pass,
// either in place or in functions shared by sections of the same shape.
#pragma once

#include <cstddef>
#include <map>
#include <string>

#include <fmt/format.h>

#include "dyngen/model.hpp"
#include "trace.hpp"

namespace dyngen::gen {

/// Operations by kind.
struct OpCounts {
  long add = 0, mul = 0, div = 0, neg = 0, sin = 0, cos = 0;
  long total() const { return add + mul + div + neg + sin + cos; }
};

/// "add 12, mul 30, div 0, neg 2, sin 1, cos 1"
std::string to_string(const OpCounts& c);

/// Counts the operations that reach an output (all of them for an unsimplified graph, whose
/// nodes the runtime all computes).
template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only = true);

/// count_ops of the live operations, split by the pass that recorded them (a kernel call's
/// loops count in the call's pass).
template <class T>
std::map<Pass, OpCounts> count_ops_by_pass(const Program<T>& program);

/// A C++ literal that reads back to the same bits: shortest round trip, with a suffix for
/// float and parentheses when negative.
std::string literal(double value);
std::string literal(float value);

/// How a function's code is laid out. Unrolled: every link's sections in place, one statement
/// per operation. Shared: sections of the same shape (the same operations on other
/// constants, as a left and a right leg, or a chain's links) call one function with a table of
/// their constants, so the code grows with the number of shapes rather than links. Lanes (C++
/// scalar code): unrolled, with the sections of limbs at the same depth that perform the same
/// operations (a quadruped's legs, a humanoid's left and right arm) computed together in
/// vector statements, 2 doubles or 4 floats to a statement. Auto: lanes where a function's
/// limbs repeat and it has fewer than max_lane_function_operations; else shared in a function
/// of at least min_shared_function_operations, unrolled below. All perform the same
/// operations, so the bits are the same.
enum class Structure { Unrolled, Shared, Auto, Lanes };

/// Below this many operations a function's straight-line code fits the instruction cache and
/// sharing only adds calls and gathers; above it, sharing ran faster in the benchmarks
/// (docs/performance.md, "Code structure").
inline constexpr long min_shared_function_operations = 1800;

/// Sections smaller than this stay in place under Structure::Shared: gathering a section's
/// inputs and calling costs about as much as a few dozen operations (docs/performance.md,
/// "Code structure").
inline constexpr std::size_t min_shared_operations = 40;

/// From this many operations (the banner's count, kernels' loops included) Structure::Auto
/// shares rather than computes in lanes: below it lanes ran faster than shared functions in
/// every function measured, and above it they took too long to compile (docs/performance.md,
/// "Code structure").
inline constexpr long max_lane_function_operations = 40000;

/// Sections shorter than this, and blocks of fewer operations in lanes, stay scalar under
/// Structure::Lanes: filling a vector's lanes costs about as much as an operation in each.
inline constexpr std::size_t min_lane_operations = 8;

/// The language the code is printed in.
enum class Language { Cpp, C };

/// Where C and C++ spell the same program differently: C has no namespace, so the names a
/// header declares carry the package's name as a prefix, and no references, so the trig comes
/// by pointer. Statements, their order and so the bits are the same in both.
struct Dialect {
  Language language = Language::Cpp;
  std::string name;  // the package's: C++ namespace, C prefix
  /// Batch code (C++ only): each value is a `lane` of this many states (GCC and clang vector
  /// types), inputs and outputs hold entry i of state l at [i * lanes + l]; 0: scalar code.
  int lanes = 0;

  bool c() const { return language == Language::C; }
  bool batch() const { return lanes > 0; }
  /// A name the header declares, as code outside the namespace sees it in C: "ur5_rnea".
  std::string external(const std::string& local) const { return c() ? name + "_" + local : local; }
  /// "nq" in C++ (a constant of the namespace), "UR5_NQ" in C (a macro).
  std::string size(const std::string& local) const;
  /// A name the header declares, from the global scope: "::ur5::rnea", "::ur5_rnea".
  std::string qualified(const std::string& local) const {
    return "::" + (c() ? external(local) : name + "::" + local);
  }
  /// A size constant from the global scope: "::ur5::nq", "UR5_NQ".
  std::string size_outside(const std::string& local) const {
    return c() ? size(local) : "::" + name + "::" + local;
  }
  /// What the header's names start with, seen from outside: "ur5::", "ur5_".
  std::string prefix() const { return c() ? name + "_" : name + "::"; }
  /// The package's header and source: "ur5_dynamics.hpp", "ur5_dynamics.c".
  std::string header() const { return name + (c() ? "_dynamics.h" : "_dynamics.hpp"); }
  std::string source() const { return name + (c() ? "_dynamics.c" : "_dynamics.cpp"); }
  /// How f passes its trig to f_trig.
  const char* trig_argument() const { return c() ? "&trig" : "trig"; }
  /// The values of templates/CMakeLists.txt.in that name the package's language.
  std::map<std::string, std::string> cmake_language() const;
  std::string discard(const std::string& x) const {
    return c() ? "(void)" + x : "static_cast<void>(" + x + ")";
  }
  const char* table() const { return c() ? "static const" : "constexpr"; }
  const char* no_throw() const { return c() ? "" : " noexcept"; }
  /// How a _trig function and joint_trig reach the trig they are given.
  const char* trig_member() const { return c() ? "trig->" : "trig."; }
  /// The _trig functions' parameter.
  std::string trig_parameter() const {
    return c()       ? fmt::format("const {}_JointTrig* trig", name)
           : batch() ? "const JointTrigBatch& trig"
                     : "const JointTrig& trig";
  }
};

struct EmittedCode {
  std::string helpers;  // namespace-scope definitions the body calls (the shared functions)
  std::string body;     // the function's statements and output stores, indented
  int sections = 0;          // runs of one body's operations in one pass
  int shared_sections = 0;   // of them, computed by a shared function
  int shared_functions = 0;
  int lane_blocks = 0;       // blocks of sections computed in vector lanes (Structure::Lanes)
  long lane_operations = 0;  // scalar operations done in them, every lane counted
  std::vector<bool> angles;  // by q index: whether the body reads sin or cos of that angle
};

/// The code of one traced function. C has no kernels (C++ templates): a C program must be traced
/// with every kernel call inlined. Batch code loads the inputs it reads into lanes first, stores
/// the outputs from lanes last, and runs a kernel call lane by lane (the scalar kernel on each
/// state's numbers), so that every lane computes the scalar code's operations.
template <class T>
EmittedCode emit_code(const Program<T>& program, const Model<double>& model, Structure structure,
                      const Dialect& dialect = {});

/// The body of joint_trig(q, trig): dyngen_sincos (dyngen_sincosf in single precision) of every
/// revolute joint's angle.
std::string emit_joint_trig(const Model<double>& model, bool single_precision,
                            const Dialect& dialect = {});

/// How a plain f(q, ...) fills its trig before calling f_trig: joint_trig(q, trig), or, where
/// its body reads only some of the revolute angles (`angles`, by q index; ur5's rnea leaves out
/// the first joint, which turns about gravity's axis), those angles alone.
std::string emit_trig_fill(const Model<double>& model, bool single_precision,
                           const std::vector<bool>& angles, const Dialect& dialect = {});

/// "revolute +z", "prismatic axis (0.6, 0, 0.8)"
std::string joint_description(const Model<double>& model, int body);

}  // namespace dyngen::gen
