// The C++ backend: the package's functions in a namespace (C++17), spelled as Dialect's
// defaults spell them.
#include <fmt/format.h>

#include "backend.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

class CppBackend final : public LanguageBackend {
 public:
  explicit CppBackend(const GenerateOptions& options) : LanguageBackend(options.name) {}

  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override {
    std::map<std::string, std::string> header = header_values(
        p, *this, summary,
        frame_declarations(p.model) + body_declarations(p) + constraint_declarations(p.model),
        declarations_);
    header.insert({{"namespace", p.ns},
                   {"joint_names", joint_name_lines(p.model)},
                   {"pinocchio", pinocchio_declarations(p.robot, p.model)}});
    files.push_back({this->header(), fill("dynamics.hpp.in", header)});
    files.push_back({source(), fill("dynamics.cpp.in",
                                    {{"banner", summary.code_banner},
                                     {"floating_point", floating_point_lines(source())},
                                     {"name", p.ns},
                                     {"namespace", p.ns},
                                     {"scalar", p.scalar},
                                     {"joint_trig", emit_joint_trig(p.model, p.single, *this)},
                                     {"support_includes", summary.support_includes()},
                                     {"definitions", definitions_}})});
  }

  void add_cmake_values(std::map<std::string, std::string>& values,
                        const PackageContext& /*p*/) const override {
    values.insert({{"standard", "C++17"},
                   {"standard_name", "C++"},
                   {"language", "CXX"},
                   {"check_flag", "check_cxx_compiler_flag"},
                   {"feature", "cxx_std_17"},
                   {"language_flags", " -fno-exceptions -fno-rtti"},
                   {"enable_check_language", ""}});
    values["sources"] += source();
  }

 private:
  /// The header's body count and names, or "" when no function has entries per body.
  static std::string body_declarations(const PackageContext& p) {
    if (!uses_bodies(p.options.algorithms)) return "";
    return fmt::format(
        "{}inline constexpr int nbodies = {};\ninline constexpr const char* body_names[nbodies] = "
        "{{\n{}}};\n",
        bodies_comment, p.model.nbodies, body_name_lines(p.model));
  }

  /// The header's constraint rows, count and names, or "" without constraints.
  static std::string constraint_declarations(const Model<double>& model) {
    if (model.nc == 0) return "";
    return fmt::format(
        "{}inline constexpr int nc = {};\ninline constexpr int nconstraints = {};\n"
        "inline constexpr const char* constraint_names[nconstraints] = {{\n{}}};\n",
        constraints_comment, model.nc, model.constraints.size(), constraint_name_lines(model));
  }

  /// The header's frame count and names, or "" without frames.
  static std::string frame_declarations(const Model<double>& model) {
    if (model.frames.empty()) return "";
    return fmt::format(
        "{}inline constexpr int nframes = {};\ninline constexpr const char* frame_names[nframes] = "
        "{{\n{}}};\n",
        frames_comment, model.frames.size(), frame_name_lines(model));
  }
};

}  // namespace

std::unique_ptr<Backend> make_cpp_backend(const GenerateOptions& options) {
  return std::make_unique<CppBackend>(options);
}

}  // namespace dyngen::gen
