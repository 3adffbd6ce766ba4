// The C backend: the package's functions in C99, every name the header declares prefixed
// with the package's name and the sizes as macros; the header is usable from C++ too. C has
// no templates, so no kernel calls, and no vector types, so no lane blocks.
#include <fmt/format.h>

#include "backend.hpp"
#include "footprint.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

class CBackend final : public LanguageBackend {
 public:
  explicit CBackend(const GenerateOptions& options) : LanguageBackend(options.name) {}

  // ---- Dialect: names
  std::string external(const std::string& local) const override { return name() + "_" + local; }
  std::string size(const std::string& local) const override { return upper(external(local)); }
  std::string qualified(const std::string& local) const override {
    return "::" + external(local);
  }
  std::string size_outside(const std::string& local) const override { return size(local); }
  std::string prefix() const override { return name() + "_"; }
  std::string header() const override { return name() + "_dynamics.h"; }
  std::string source() const override { return name() + "_dynamics.c"; }

  // ---- Dialect: statements and declarations
  bool kernel_calls() const override { return false; }
  bool lane_blocks() const override { return false; }
  std::string discard(const std::string& x) const override { return "(void)" + x; }
  const char* table() const override { return "static const"; }
  const char* no_throw() const override { return ""; }
  const char* trig_member() const override { return "trig->"; }
  std::string trig_parameter() const override { return "const " + trig_type() + "* trig"; }
  const char* trig_argument() const override { return "&trig"; }
  std::string zero_trig() const override {
    return "static const " + trig_type() + " trig = {0};";
  }

  // ---- Dialect: compiling
  const char* title() const override { return "C"; }
  const char* language() const override { return "c"; }
  const std::vector<std::string>& compiler(const Toolchain& toolchain) const override {
    return toolchain.c;
  }
  const char* standard_flag() const override { return "-std=c99"; }
  std::vector<std::string> language_flags() const override { return {}; }

  // ---- Backend
  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override {
    std::map<std::string, std::string> h = header_values(
        p, *this, summary,
        frame_declarations(p.model) + body_declarations(p) + constraint_declarations(p.model),
        declarations_);
    h.insert({{"name", p.ns}, {"NAME", upper(p.ns)}});
    files.push_back({header(), fill("dynamics.h.in", h)});
    files.push_back(
        {source(), fill("dynamics.c.in", {{"banner", summary.code_banner},
                                          {"floating_point", floating_point_lines(source())},
                                          {"name", p.ns},
                                          {"NAME", upper(p.ns)},
                                          {"scalar", p.scalar},
                                          {"joint_names", joint_name_lines(p.model)},
                                          {"frame_names", frame_names_definition(p.model) +
                                                              body_names_definition(p) +
                                                              constraint_names_definition(p.model)},
                                          {"joint_trig", emit_joint_trig(p.model, p.single, *this)},
                                          {"support_includes", summary.support_includes()},
                                          {"definitions", definitions_}})});
  }

  void add_cmake_values(std::map<std::string, std::string>& values,
                        const PackageContext& /*p*/) const override {
    values.insert(
        {{"standard", "C99"},
         {"standard_name", "C"},
         {"language", "C"},
         {"check_flag", "check_c_compiler_flag"},
         {"feature", "c_std_99"},
         {"language_flags", ""},
         {"enable_check_language", "  enable_language(CXX)  # the check is C++ (GoogleTest)\n"}});
    values["sources"] += source();
  }

 private:
  /// The header's frame count and names, or "" without frames.
  std::string frame_declarations(const Model<double>& model) const {
    if (model.frames.empty()) return "";
    return fmt::format("{}#define {} {}\nextern const char* const {}[{}];\n", frames_comment,
                       size("nframes"), model.frames.size(), external("frame_names"),
                       size("nframes"));
  }

  /// The header's constraint rows, count and names, or "" without constraints.
  std::string constraint_declarations(const Model<double>& model) const {
    if (model.nc == 0) return "";
    return fmt::format("{}#define {} {}\n#define {} {}\nextern const char* const {}[{}];\n",
                       constraints_comment, size("nc"), model.nc, size("nconstraints"),
                       model.constraints.size(), external("constraint_names"),
                       size("nconstraints"));
  }

  /// The source's definition of the constraint names, or "".
  std::string constraint_names_definition(const Model<double>& model) const {
    if (model.nc == 0) return "";
    return fmt::format("\nconst char* const {}[{}] = {{\n{}}};\n", external("constraint_names"),
                       size("nconstraints"), constraint_name_lines(model));
  }

  /// The header's body count and names, or "" when no function has entries per body.
  std::string body_declarations(const PackageContext& p) const {
    if (!uses_bodies(p.options.algorithms)) return "";
    return fmt::format("{}#define {} {}\nextern const char* const {}[{}];\n", bodies_comment,
                       size("nbodies"), p.model.nbodies, external("body_names"), size("nbodies"));
  }

  /// The source's definition of the body names, or "".
  std::string body_names_definition(const PackageContext& p) const {
    if (!uses_bodies(p.options.algorithms)) return "";
    return fmt::format("\nconst char* const {}[{}] = {{\n{}}};\n", external("body_names"),
                       size("nbodies"), body_name_lines(p.model));
  }

  /// The source's definition of the frame names, or "".
  std::string frame_names_definition(const Model<double>& model) const {
    if (model.frames.empty()) return "";
    return fmt::format("\nconst char* const {}[{}] = {{\n{}}};\n", external("frame_names"),
                       size("nframes"), frame_name_lines(model));
  }
};

}  // namespace

std::unique_ptr<Backend> make_c_backend(const GenerateOptions& options) {
  return std::make_unique<CBackend>(options);
}

}  // namespace dyngen::gen
