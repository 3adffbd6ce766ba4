// The package's backends: one object per part of the package that prints the traced program,
// each owning its functions' texts, its files and its fragments of the check and CMakeLists.
// C++ and C are languages (--lang picks one); batches and the Python module are added by
// their options. A new backend is one file (backend_NAME.cpp) and one line in backend.cpp.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dyngen/model.hpp"
#include "emit.hpp"
#include "generate.hpp"
#include "output.hpp"
#include "robot.hpp"

namespace dyngen::gen {

/// What every backend knows of the package it writes: the robot, its model, the options.
struct PackageContext {
  PackageContext(const Robot& r, const Model<double>& m, const GenerateOptions& o)
      : robot(r),
        model(m),
        options(o),
        ns(o.name),
        scalar(o.single_precision ? "float" : "double"),
        single(o.single_precision) {}

  const Robot& robot;
  const Model<double>& model;
  const GenerateOptions& options;
  std::string ns, scalar;
  bool single;
};

/// One algorithm, traced, as every backend receives it.
struct TracedFunction {
  const AlgorithmSpec<double>& spec;
  OpCounts generated;       // the traced program's operations
  const EmittedCode& code;  // the program as the package's language prints it
  /// The program printed in another dialect, with its operations. Without vector_kernels, a
  /// program whose kernel calls run in vector lanes is traced again with them inlined (a
  /// batch runs its states in the lanes already).
  std::function<std::pair<EmittedCode, OpCounts>(const Dialect&, bool vector_kernels)> print;
};

/// What the backends' files say of the whole package.
struct PackageSummary {
  const std::vector<FunctionCounts>& counts;
  std::string code_banner;  // the banner as // comments
  bool calls_kernels;       // some function calls dyngen_kernels.hpp
  std::string hash_banner;  // as # comments (CMake, Python, TOML)
  bool uses_lie = false;    // some function calls dyngen_lie.h (integrate, difference)

  /// The #include lines of the support headers the functions call beyond dyngen_sincos.h.
  std::string support_includes() const {
    return std::string(calls_kernels ? "#include \"dyngen_kernels.hpp\"\n" : "") +
           (uses_lie ? "#include \"dyngen_lie.h\"\n" : "");
  }
};

/// The lines that open every source file of generated code (floating_point.in): they hold its
/// floating-point semantics against the flags of a build that compiles it (`file`: its name, for
/// the error under fast-math).
std::string floating_point_lines(const std::string& file);

class Backend {
 public:
  virtual ~Backend() = default;
  /// The dialect the backend prints the program in, or null for one that prints no program.
  virtual const Dialect* dialect() const { return nullptr; }
  /// Adds function f's texts to the backend's files.
  virtual void add_function(const PackageContext& p, const TracedFunction& f) = 0;
  /// f's case in the check, or "".
  virtual std::string check_case(const PackageContext& /*p*/, const TracedFunction& /*f*/) const {
    return "";
  }
  /// The check's #include lines for the backend's header, beyond the language's.
  virtual std::string check_include(const PackageContext& /*p*/) const { return ""; }
  /// Appends the backend's files, once every function is added.
  virtual void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                         const PackageSummary& summary) const = 0;
  /// Sets or extends the values of templates/CMakeLists.txt.in: the language's, `sources` of
  /// the library and `targets` (CMake text that adds targets).
  virtual void add_cmake_values(std::map<std::string, std::string>& /*values*/,
                                const PackageContext& /*p*/) const {}
};

/// A backend of the registry (backend.cpp).
struct BackendEntry {
  const char* name;  // "c++", "batch"
  /// null for a language, of which --lang picks one per package; else whether the options
  /// add the backend to the package. A package holds its language first, then the others in
  /// the registry's order.
  bool (*added)(const GenerateOptions& options);
  /// The backend for a package with these options; InputError when they do not allow it.
  std::unique_ptr<Backend> (*make)(const GenerateOptions& options);
  const char* help;  // for --lang: "c (C99, ...)"
};

const std::vector<BackendEntry>& backend_registry();

/// The languages --lang takes, in the registry's order.
std::vector<std::string> language_names();

/// --lang's help: each language with its registry help.
std::string language_help();

/// The backends of a package with these options, its language first; InputError for an
/// unknown language or options that a backend does not allow.
std::vector<std::unique_ptr<Backend>> package_backends(const GenerateOptions& options);

/// The algorithms listed, with those that the PyTorch functions' backward calls (--torch:
/// backend_torch.cpp), in `known`'s order.
std::vector<Algorithm> with_torch_backwards(const std::vector<Algorithm>& listed,
                                            const std::vector<Algorithm>& known);

/// The functions NAME_torch.py wraps: --torch's default --algorithms.
std::vector<Algorithm> torch_default_algorithms();

/// The dialect of language (a --lang name) for a package named name, or InputError.
std::unique_ptr<Backend> language_backend(const std::string& language, const std::string& name);

// ---- what several backends print

std::string upper(std::string s);

/// "nq", "UR5_NQ * 3": an array's extent as the dialect spells sizes.
std::string extent_in(const Extent& e, const Dialect& dialect);

/// head ("void name("), the parameters separated by commas, then end (") noexcept"), wrapped at
/// 100 columns with continuation lines under the first parameter.
std::string wrapped_parameters(const std::string& head, const std::vector<std::string>& parameters,
                               const std::string& end);

/// "void name(a, b, ...) noexcept" (C: no noexcept) wrapped at 100 columns, continuation lines
/// under the first parameter.
std::string declaration(const std::string& name, const std::vector<std::string>& parameters,
                        const Dialect& dialect);

/// The generated function's parameters: the inputs, with `trig` after q in the _trig form, then
/// the outputs; batch arrays hold `lanes` states.
std::vector<std::string> parameters(const AlgorithmSpec<double>& spec, const std::string& scalar,
                                    bool trig, const Dialect& dialect);

/// The arguments the check passes to f (x[0].data(), ..., y[0].data(), ...) and those that f
/// passes to f_trig (q, trig, v, ..., tau).
std::pair<std::string, std::string> call_arguments(const AlgorithmSpec<double>& spec,
                                                   const Dialect& dialect);

/// The definitions of f and f_trig (function.cpp.in) with the shared functions f's body calls.
std::string function_definitions(const PackageContext& p, const Dialect& dialect,
                                 const AlgorithmSpec<double>& spec, const EmittedCode& code,
                                 const std::string& summary, const std::string& counts);

/// A language of the package (C++, C): f and f_trig in its header and source
/// (function.hpp.in, function.cpp.in) and their cases in the check, spelled by its dialect.
class LanguageBackend : public Backend, public Dialect {
 public:
  using Dialect::Dialect;
  const Dialect* dialect() const override { return this; }
  void add_function(const PackageContext& p, const TracedFunction& f) override;
  std::string check_case(const PackageContext& p, const TracedFunction& f) const override;

 protected:
  std::string declarations_, definitions_;  // of the functions added
};

/// The header's comment before the frames' count and names.
inline constexpr const char* frames_comment =
    "\n/// The frames whose placements, Jacobians or accelerations the functions compute, in "
    "order\n/// (--frames).\n";

/// The header's comment before the bodies' count and names.
inline constexpr const char* bodies_comment =
    "\n/// The bodies, in order: the links, each with those on fixed joints below it merged in.\n"
    "/// The regressor's columns hold 10 standard parameters per body.\n";

/// The bodies' names as initialiser lines, "    \"forearm_link\",\n" each.
std::string body_name_lines(const Model<double>& model);

/// "    \"shoulder_pan_joint\",\n..." : the velocity names as initialiser lines.
std::string joint_name_lines(const Model<double>& model);

/// The index maps between the package's q and v and Pinocchio's for the same URDF (README,
/// "Coordinates beside Pinocchio's"): q_pinocchio[i] = q[to_q[i]] and q[i] =
/// q_pinocchio[from_q[i]], the same for v; or, when Pinocchio's coordinates are not a
/// reordering of these, no maps and the reason, in words.
struct PinocchioMaps {
  std::vector<int> to_q, from_q, to_v, from_v;
  std::string missing;
};
PinocchioMaps pinocchio_maps(const Robot& robot, const Model<double>& model);

/// text as /// comment lines of at most 100 columns, broken at spaces.
std::string comment_lines(const std::string& text);

/// The header's maps (pinocchio_maps) as C++ declarations, or a comment that says why not.
std::string pinocchio_declarations(const Robot& robot, const Model<double>& model);

/// The frames' names as initialiser lines, "    \"tool0\",\n" each.
std::string frame_name_lines(const Model<double>& model);

/// The header's comment before the constraints' rows and names.
inline constexpr const char* constraints_comment =
    "\n/// The constraints (--contacts, a chain spec's loops), in order: lambda and impulse\n"
    "/// hold 3 entries for each one named :3d and 6 for each :6d, nc in all.\n";

/// The constraints' names as initialiser lines, "    \"FL_FOOT:3d\",\n" each.
std::string constraint_name_lines(const Model<double>& model);

/// The trig's values in a header: trig_entries, its arrays' length (nq: the size's name, with
/// the mimic joints' own angles added), and mimic_trig, the comment lines on those entries.
std::map<std::string, std::string> trig_values(const Model<double>& model, const std::string& nq);

/// The values the language's header template shares: banner, robot, scalar, sizes, gravity,
/// structure, the arrays' documentation, frames (as frame_declarations gives them) and
/// declarations.
std::map<std::string, std::string> header_values(const PackageContext& p, const Dialect& dialect,
                                                 const PackageSummary& summary,
                                                 const std::string& frames,
                                                 const std::string& declarations);

}  // namespace dyngen::gen
