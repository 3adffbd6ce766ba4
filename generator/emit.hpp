// Schedules a traced program and prints it in a backend's dialect: live nodes in creation order
// (the algorithm's order), one operation per statement, grouped and labelled by body and pass,
// either in place or in functions shared by sections of the same shape.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "dyngen/model.hpp"
#include "trace.hpp"

namespace dyngen::gen {

/// Operations by kind; fn: calls of lie.h's functions.
struct OpCounts {
  long add = 0, mul = 0, div = 0, neg = 0, sin = 0, cos = 0, fn = 0;
  long total() const { return add + mul + div + neg + sin + cos + fn; }
};

/// "add 12, mul 30, div 0, neg 2, sin 1, cos 1", and ", fn 3" where there are calls of lie.h
std::string to_string(const OpCounts& c);

/// Counts the operations that reach an output (all of them for an unsimplified graph, whose
/// nodes the runtime all computes).
template <class T>
OpCounts count_ops(const Program<T>& program, bool live_only = true);

/// The operations of the nodes marked in counted (by node id).
template <class T>
OpCounts count_ops(const Program<T>& program, const std::vector<bool>& counted);

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

struct Toolchain;

/// How a backend spells a traced program (Halide's CodeGen_C and its subclasses): names,
/// types, statements, declarations and how the code is compiled. The answers here are C++'s,
/// the language the other backends derive from: C (backend_c.cpp) has no namespace, so the
/// names a header declares carry the package's name as a prefix, and no references, so the
/// trig comes by pointer; batches (backend_batch.cpp) hold each value in vector lanes. The
/// statements, their order and so the bits are the same in every dialect.
class Dialect {
 public:
  explicit Dialect(std::string name = "") : name_(std::move(name)) {}
  virtual ~Dialect() = default;

  /// The package's name: C++ namespace, C prefix.
  const std::string& name() const { return name_; }

  // ---- names
  /// A name the header declares, as code outside the namespace sees it in C: "ur5_rnea".
  virtual std::string external(const std::string& local) const { return local; }
  /// "nq" in C++ (a constant of the namespace), "UR5_NQ" in C (a macro).
  virtual std::string size(const std::string& local) const { return local; }
  /// A name the header declares, from the global scope: "::ur5::rnea", "::ur5_rnea".
  virtual std::string qualified(const std::string& local) const {
    return "::" + name_ + "::" + local;
  }
  /// A size constant from the global scope: "::ur5::nq", "UR5_NQ".
  virtual std::string size_outside(const std::string& local) const {
    return "::" + name_ + "::" + local;
  }
  /// What the header's names start with, seen from outside: "ur5::", "ur5_".
  virtual std::string prefix() const { return name_ + "::"; }
  /// The package's header and source: "ur5_dynamics.hpp", "ur5_dynamics.c".
  virtual std::string header() const { return name_ + "_dynamics.hpp"; }
  virtual std::string source() const { return name_ + "_dynamics.cpp"; }
  /// Algorithm a's function: "rnea", "ur5_rnea", "rnea_batch" (its _trig form adds "_trig").
  virtual std::string function(const std::string& a) const { return external(a); }
  /// The function that fills a trig from q, and the trig's type.
  virtual std::string joint_trig() const { return external("joint_trig"); }
  virtual std::string trig_type() const { return external("JointTrig"); }

  // ---- statements
  /// States per value (batches: vector lanes); 0: one state, scalar code.
  virtual int lanes() const { return 0; }
  /// Whether the code may call dyngen_kernels.hpp (C++ templates).
  virtual bool kernel_calls() const { return true; }
  /// Whether a function's repeated limbs may be computed in vector statements (GCC's and
  /// clang's vector types) within scalar code.
  virtual bool lane_blocks() const { return true; }
  /// The type of each computed value.
  virtual std::string value_type(const std::string& scalar) const { return scalar; }
  /// Entry index of input array: "q[3]".
  virtual std::string input(const std::string& array, int index) const {
    return array + "[" + std::to_string(index) + "]";
  }
  /// sin or cos (function) of q[index], read from the trig.
  virtual std::string trig_value(const char* function, int index) const;
  /// The call of a function of lie.h (its name for the scalar) on computed values: "f(x)".
  virtual std::string function_call(const std::string& function,
                                    const std::vector<std::string>& arguments) const {
    return function + "(" + arguments[0] + (arguments.size() > 1 ? ", " + arguments[1] : "") + ")";
  }
  /// A constant as an element of an array of computed values.
  virtual std::string element(const std::string& constant) const { return constant; }
  /// The statement that stores value into entry k of output array.
  virtual std::string store(std::string_view array, std::size_t k, const std::string& value) const;
  /// Where entry k of an array begins, as an index: "k", or "k * lanes".
  virtual std::string entry(std::size_t k) const { return std::to_string(k); }
  /// An input or trig value that the body reads: its name and where it comes from.
  struct Read {
    std::string value, from;
    int index;
  };
  /// What the body does with the values it reads before its statements (batches load them
  /// into lanes).
  virtual std::string load(const std::vector<Read>& /*reads*/) const { return ""; }
  /// The statements of a kernel call (kernel: its qualified name) over its arguments, which
  /// end with the arrays it reads and writes; scalar: the scalar type.
  virtual std::string kernel_call(const KernelRecord& call, std::vector<std::string> arguments,
                                  const std::string& kernel, const std::string& scalar) const;
  /// dyngen_sincos (sincos: its name) of q[first .. first + count) into trig's sin_q and cos_q.
  virtual std::string sincos_run(int first, int count, const char* sincos,
                                 const std::string& trig) const;
  /// q[k] in joint_trig, for the angles of mimic joints.
  virtual std::string q_entry(int k) const { return fmt::format("q[{}]", k); }
  /// dyngen_sincos of `angle` (an expression of q_entry) into the trig's entry k; `what` names
  /// the angle in a comment.
  virtual std::string sincos_angle(int k, const std::string& angle, const char* sincos,
                                   const std::string& trig, const std::string& what) const;

  // ---- declarations
  /// A statement that uses x without effect.
  virtual std::string discard(const std::string& x) const {
    return "static_cast<void>(" + x + ")";
  }
  /// How a table of constants is declared.
  virtual const char* table() const { return "constexpr"; }
  /// What a function's declaration ends with.
  virtual const char* no_throw() const { return " noexcept"; }
  /// How a _trig function and joint_trig reach the trig they are given.
  virtual const char* trig_member() const { return "trig."; }
  /// The _trig functions' parameter, and how f passes its trig to f_trig.
  virtual std::string trig_parameter() const { return "const " + trig_type() + "& trig"; }
  virtual const char* trig_argument() const { return "trig"; }
  /// f's trig declared when f_trig reads no angle: constant zeros, so that no sin or cos runs
  /// for nothing (static: GCC 12 takes a local's zeros for none when f_trig is cloned, and warns)
  virtual std::string zero_trig() const { return "static const " + trig_type() + " trig{};"; }

  // ---- compiling
  /// The language's name for people ("C++") and in --lang ("c++").
  virtual const char* title() const { return "C++"; }
  virtual const char* language() const { return "c++"; }
  /// The toolchain's compiler for the language, its standard, and the flags it adds.
  virtual const std::vector<std::string>& compiler(const Toolchain& toolchain) const;
  virtual const char* standard_flag() const { return "-std=c++17"; }
  virtual std::vector<std::string> language_flags() const {
    return {"-fno-exceptions", "-fno-rtti"};
  }

 private:
  std::string name_;
};

/// "    f(a, b, ...);" (indent first) with the arguments wrapped before 100 columns under the
/// first.
std::string wrapped_call(const std::string& function, const std::vector<std::string>& arguments,
                         const std::string& indent = "    ");

struct EmittedCode {
  std::string helpers;  // namespace-scope definitions the body calls (the shared functions)
  std::string body;     // the function's statements and output stores, indented
  int sections = 0;          // runs of one body's operations in one pass
  int shared_sections = 0;   // of them, computed by a shared function
  int shared_functions = 0;
  int lane_blocks = 0;       // blocks of sections computed in vector lanes (Structure::Lanes)
  long lane_operations = 0;  // scalar operations done in them, every lane counted
  std::vector<bool> angles;  // by trig entry: whether the body reads sin or cos of that angle
};

/// The code of one traced function. C has no kernels (C++ templates): a C program must be traced
/// with every kernel call inlined. Batch code loads the inputs it reads into lanes first, stores
/// the outputs from lanes last, and runs a kernel call lane by lane (the scalar kernel on each
/// state's numbers), so that every lane computes the scalar code's operations.
template <class T>
EmittedCode emit_code(const Program<T>& program, const Model<double>& model, Structure structure,
                      const Dialect& dialect = Dialect());

/// The trig's entries: nq, and one after them for each mimic joint with an angle of its own
/// (own_angle_mimics).
int trig_entries(const Model<double>& model);

/// The body of joint_trig(q, trig): dyngen_sincos (dyngen_sincosf in single precision) of every
/// revolute joint's angle, and of each mimic joint's own.
std::string emit_joint_trig(const Model<double>& model, bool single_precision,
                            const Dialect& dialect = Dialect());

/// How a plain f(q, ...) declares and fills its trig before calling f_trig: joint_trig(q, trig),
/// or, where its body reads only some of the revolute angles (`angles`, by q index; ur5's rnea
/// leaves out the first joint, which turns about gravity's axis), those angles alone, or zeros
/// where it reads none.
std::string emit_trig_fill(const Model<double>& model, bool single_precision,
                           const std::vector<bool>& angles, const Dialect& dialect = Dialect());

/// "revolute +z", "prismatic axis (0.6, 0, 0.8)"
std::string joint_description(const Model<double>& model, int body);

}  // namespace dyngen::gen
