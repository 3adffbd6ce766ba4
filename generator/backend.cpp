#include "backend.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "names.hpp"
#include "template.hpp"

namespace dyngen::gen {

// Each backend's file defines its make function.
std::unique_ptr<Backend> make_cpp_backend(const GenerateOptions& options);
std::unique_ptr<Backend> make_c_backend(const GenerateOptions& options);
std::unique_ptr<Backend> make_batch_backend(const GenerateOptions& options);
std::unique_ptr<Backend> make_python_backend(const GenerateOptions& options);
std::unique_ptr<Backend> make_torch_backend(const GenerateOptions& options);
std::unique_ptr<Backend> make_eigen_backend(const GenerateOptions& options);

std::string floating_point_lines(const std::string& file) {
  return fill("floating_point.in", {{"file", file}});
}

const std::vector<BackendEntry>& backend_registry() {
  static const std::vector<BackendEntry> registry{
      {"c++", nullptr, make_cpp_backend, "c++ (C++17, in a namespace)"},
      {"c", nullptr, make_c_backend, "c (C99, every name prefixed, a header usable from C and C++)"},
      {"batch", [](const GenerateOptions& o) { return o.batch > 0; }, make_batch_backend, ""},
      {"python", [](const GenerateOptions& o) { return o.python; }, make_python_backend, ""},
      {"torch", [](const GenerateOptions& o) { return o.torch; }, make_torch_backend, ""},
      {"eigen", [](const GenerateOptions& o) { return o.language == "c++"; }, make_eigen_backend,
       ""},
  };
  return registry;
}

std::vector<std::string> language_names() {
  std::vector<std::string> names;
  for (const BackendEntry& b : backend_registry())
    if (!b.added) names.emplace_back(b.name);
  return names;
}

std::string language_help() {
  std::vector<std::string> languages;
  for (const BackendEntry& b : backend_registry())
    if (!b.added) languages.emplace_back(b.help);
  std::string text = "language of the code: ";
  for (std::size_t k = 0; k < languages.size(); ++k)
    text += (k == 0 ? "" : k + 1 < languages.size() ? ", " : " or ") + languages[k];
  return text + "; the same functions and bits";
}

std::vector<std::unique_ptr<Backend>> package_backends(const GenerateOptions& options) {
  std::vector<std::unique_ptr<Backend>> backends;
  for (const BackendEntry& b : backend_registry())
    if (!b.added && options.language == b.name) backends.push_back(b.make(options));
  if (backends.empty())
    throw InputError(fmt::format("no language '{}': dyngen prints {}",
                                 safe_text(options.language), fmt::join(language_names(), ", ")));
  for (const BackendEntry& b : backend_registry())
    if (b.added && b.added(options)) backends.push_back(b.make(options));
  return backends;
}

std::unique_ptr<Backend> language_backend(const std::string& language, const std::string& name) {
  GenerateOptions options;
  options.name = name;
  options.language = language;
  return std::move(package_backends(options).front());
}

std::string upper(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

std::string extent_in(const Extent& e, const Dialect& dialect) {
  return extent_text(e, dialect.size("nq"), dialect.size("nv"), dialect.size("nframes"),
                     dialect.size("nbodies"), dialect.size("nc"));
}

std::string declaration(const std::string& name, const std::vector<std::string>& parameters,
                        const Dialect& dialect) {
  return wrapped_parameters(fmt::format("void {}(", name), parameters,
                            std::string(")") + dialect.no_throw());
}

std::string wrapped_parameters(const std::string& head, const std::vector<std::string>& parameters,
                               const std::string& end) {
  const std::size_t indent = head.size();
  std::string text = head;
  std::size_t column = indent;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string item = k + 1 < parameters.size() ? parameters[k] + ", " : parameters[k] + end;
    if (column + item.size() > 100 && column > indent) {
      while (text.back() == ' ') text.pop_back();
      text += fmt::format("\n{:{}}", "", indent);
      column = indent;
    }
    text += item;
    column += item.size();
  }
  return text;
}

std::vector<std::string> parameters(const AlgorithmSpec<double>& spec, const std::string& scalar,
                                    bool trig, const Dialect& dialect) {
  const std::string lanes = dialect.lanes() > 0 ? " * lanes" : "";
  std::vector<std::string> out;
  for (const ArraySpec& a : spec.inputs) {
    out.push_back(
        fmt::format("const {} {}[{}{}]", scalar, a.name, extent_in(a.extent, dialect), lanes));
    if (trig && a.name == "q") out.push_back(dialect.trig_parameter());
  }
  for (const ArraySpec& a : spec.outputs)
    out.push_back(fmt::format("{} {}[{}{}]", scalar, a.name, extent_in(a.extent, dialect), lanes));
  return out;
}

std::pair<std::string, std::string> call_arguments(const AlgorithmSpec<double>& spec,
                                                   const Dialect& dialect) {
  std::string trig_arguments, arguments;
  for (const ArraySpec& x : spec.inputs) {
    trig_arguments += fmt::format("{}{}", trig_arguments.empty() ? "" : ", ", x.name);
    if (x.name == "q") trig_arguments += fmt::format(", {}", dialect.trig_argument());
  }
  for (const ArraySpec& y : spec.outputs) trig_arguments += fmt::format(", {}", y.name);
  for (std::size_t k = 0; k < spec.inputs.size(); ++k)
    arguments += fmt::format("{}x[{}].data()", k == 0 ? "" : ", ", k);
  for (std::size_t k = 0; k < spec.outputs.size(); ++k)
    arguments += fmt::format(", y[{}].data()", k);
  return {arguments, trig_arguments};
}

std::string function_definitions(const PackageContext& p, const Dialect& dialect,
                                 const AlgorithmSpec<double>& spec, const EmittedCode& code,
                                 const std::string& summary, const std::string& counts) {
  const std::string a(spec.name);
  const std::string trig_arguments = call_arguments(spec, dialect).second;
  const bool reads_angles = std::ranges::any_of(code.angles, [](bool read) { return read; });
  std::string text = code.helpers.empty() ? "" : "\n" + code.helpers;
  return text + fill("function.cpp.in",
                     {{"trig_name", dialect.function(a) + "_trig"},
                      {"trig_note", reads_angles ? "sin and cos in " + dialect.joint_trig()
                                                 : std::string("it reads no joint angle")},
                      {"summary", summary},
                      {"declaration", declaration(dialect.function(a),
                                                  parameters(spec, p.scalar, false, dialect),
                                                  dialect)},
                      {"trig_declaration", declaration(dialect.function(a) + "_trig",
                                                       parameters(spec, p.scalar, true, dialect),
                                                       dialect)},
                      {"trig_arguments", trig_arguments},
                      {"trig_fill", emit_trig_fill(p.model, p.single, code.angles, dialect)},
                      {"counts", counts},
                      {"body", code.body}});
}

void LanguageBackend::add_function(const PackageContext& p, const TracedFunction& f) {
  const std::string a(f.spec.name), summary(f.spec.summary);
  declarations_ +=
      fill("function.hpp.in",
           {{"summary", summary},
            {"declaration",
             declaration(function(a), parameters(f.spec, p.scalar, false, *this), *this)},
            {"trig_declaration", declaration(function(a) + "_trig",
                                             parameters(f.spec, p.scalar, true, *this), *this)}}) +
      "\n";
  definitions_ += function_definitions(p, *this, f.spec, f.code, summary, to_string(f.generated));
}

std::string LanguageBackend::check_case(const PackageContext& p, const TracedFunction& f) const {
  const std::string a(f.spec.name);
  return fill("function_check.cpp.in", {{"name", a},
                                        {"namespace", p.ns},
                                        {"call", qualified(a)},
                                        {"arguments", call_arguments(f.spec, *this).first}});
}

namespace {

PinocchioMaps no_maps(const std::string& why) {
  PinocchioMaps maps;
  maps.missing = why;
  return maps;
}

}  // namespace

PinocchioMaps pinocchio_maps(const Robot& robot, const Model<double>& model) {
  if (!robot.pinocchio_missing.empty()) return no_maps(robot.pinocchio_missing);
  if (!robot.locked.empty()) return no_maps("joints are locked here, not in Pinocchio's model");
  std::vector<int> bodies;  // in Pinocchio's order: the free joint of --floating-base first
  for (int i = 0; i < model.nbodies; ++i)
    if (model.parent[i] < 0 && model.joint_type[i] == JointType::Free) bodies.push_back(i);
  for (const std::string& name : robot.pinocchio_order) {
    const auto at = std::find(model.joint_name.begin(), model.joint_name.end(), name);
    const int i = static_cast<int>(at - model.joint_name.begin());
    if (at == model.joint_name.end() || (!model.mimic.empty() && model.mimic[i] >= 0))
      return no_maps(fmt::format("joint '{}' has no coordinate of its own here (a mimic joint: "
                                 "--mimic-independent gives it one, as Pinocchio's parser does)",
                                 safe_text(name)));
    bodies.push_back(i);
  }
  PinocchioMaps maps;
  for (const int i : bodies) {
    const int q = model.q_index[i], v = model.v_index[i];
    if (model.joint_type[i] == JointType::Free)  // Pinocchio: x, y, z, qx, qy, qz, qw
      maps.to_q.insert(maps.to_q.end(), {q, q + 1, q + 2, q + 4, q + 5, q + 6, q + 3});
    else
      for (int k = 0; k < joint_nq(model.joint_type[i]); ++k) maps.to_q.push_back(q + k);
    for (int k = 0; k < joint_nv(model.joint_type[i]); ++k) maps.to_v.push_back(v + k);
  }
  if (static_cast<int>(maps.to_q.size()) != model.nq ||
      static_cast<int>(maps.to_v.size()) != model.nv)
    return no_maps("some joints are not in Pinocchio's model");
  maps.from_q.resize(maps.to_q.size());
  maps.from_v.resize(maps.to_v.size());
  for (std::size_t k = 0; k < maps.to_q.size(); ++k)
    maps.from_q[maps.to_q[k]] = static_cast<int>(k);
  for (std::size_t k = 0; k < maps.to_v.size(); ++k)
    maps.from_v[maps.to_v[k]] = static_cast<int>(k);
  return maps;
}

std::string pinocchio_declarations(const Robot& robot, const Model<double>& model) {
  const PinocchioMaps maps = pinocchio_maps(robot, model);
  const std::string head =
      "\n/// Pinocchio's coordinates for the same URDF (pinocchio::urdf::buildModel, with\n"
      "/// JointModelFreeFlyer under --floating-base; README, \"Coordinates beside Pinocchio's\"):";
  if (!maps.missing.empty())
    return head + "\n" + comment_lines("No index maps: " + maps.missing + ".");
  const auto list = [](const std::vector<int>& v) {
    return fmt::format("{{{}}}", fmt::join(v, ", "));
  };
  return fmt::format(
      "{}\n/// joints depth first from the root link, siblings by name; the free joint's "
      "quaternion\n/// w last. q_pinocchio[i] = q[to_pinocchio_q[i]], q[i] = "
      "q_pinocchio[from_pinocchio_q[i]];\n"
      "/// v, a, tau, qdd and the derivatives' rows and columns by the _v maps.\n"
      "inline constexpr int to_pinocchio_q[nq] = {};\n"
      "inline constexpr int from_pinocchio_q[nq] = {};\n"
      "inline constexpr int to_pinocchio_v[nv] = {};\n"
      "inline constexpr int from_pinocchio_v[nv] = {};\n",
      head, list(maps.to_q), list(maps.from_q), list(maps.to_v), list(maps.from_v));
}

std::string joint_name_lines(const Model<double>& model) {
  std::string joint_names;
  const std::vector<std::string> names = velocity_names(model);
  for (std::size_t k = 0; k < names.size(); ++k)
    joint_names +=
        fmt::format("    {},{}", string_literal(names[k]), k + 1 < names.size() ? "\n" : "");
  return joint_names;
}

std::string body_name_lines(const Model<double>& model) {
  std::string names;
  for (const std::string& name : model.body_name)
    names += fmt::format("    {},\n", string_literal(name));
  return names;
}

std::string frame_name_lines(const Model<double>& model) {
  std::string names;
  for (const Frame<double>& f : model.frames)
    names += fmt::format("    {},\n", string_literal(f.name));
  return names;
}

std::string constraint_name_lines(const Model<double>& model) {
  std::string names;
  for (const Constraint<double>& c : model.constraints)
    names += fmt::format("    {},\n", string_literal(c.name));
  return names;
}

namespace {

/// The header's lines on how q and v hold each free and ball joint, and what each mimic joint
/// follows.
std::vector<std::string> free_joint_lines(const Model<double>& model) {
  std::vector<std::string> free_joints;
  for (int i = 0; i < model.nbodies; ++i) {
    if (is_mimic(model, i)) {
      const int p = model.mimic[i];
      free_joints.push_back(fmt::format(
          "mimic joint '{}' has no entry: it follows '{}', q = {} q[{}] + {}, v = {} v[{}]",
          safe_text(model.joint_name[i]), safe_text(model.joint_name[p]),
          model.mimic_multiplier[i], model.q_index[p], model.mimic_offset[i],
          model.mimic_multiplier[i], model.v_index[p]));
    }
    if (model.joint_type[i] == JointType::Ball) {
      free_joints.push_back(fmt::format(
          "ball joint '{}': q[{}..{}] = unit quaternion w, x, y, z of the body in its parent;",
          safe_text(model.joint_name[i]), model.q_index[i], model.q_index[i] + 3));
      free_joints.push_back(fmt::format(
          "v[{}..{}] = angular velocity in the body's own frame (tau alike: moment)",
          model.v_index[i], model.v_index[i] + 2));
    }
    if (model.joint_type[i] == JointType::Free) {
      free_joints.push_back(fmt::format(
          "free joint '{}': q[{}..{}] = position of the body in its parent's frame, then",
          safe_text(model.joint_name[i]), model.q_index[i], model.q_index[i] + 6));
      free_joints.push_back(fmt::format(
          "its unit quaternion w, x, y, z; v[{}..{}] = linear, then angular velocity in the",
          model.v_index[i], model.v_index[i] + 5));
      free_joints.push_back("body's own frame (tau alike: force, then moment)");
    }
  }
  return free_joints;
}

/// Whether an array holds a matrix (rows of several entries), row-major.
bool is_matrix(const Extent& e) {
  return e.size == Extent::NvNv || e.size == Extent::NcNv || e.per_body ||
         (e.count > 1 && e.size != Extent::One);
}

/// The header's list of the arrays that the requested functions take, each once, and how q holds
/// the free joints' positions (`free_joints`: lines to add to q's); `eigen`, when not empty, the
/// header of Eigen overloads, named after each matrix.
std::string array_docs(const std::vector<Algorithm>& algorithms,
                       const std::vector<std::string>& free_joints, const Dialect& dialect,
                       const std::string& eigen) {
  std::vector<std::pair<std::string, const ArraySpec*>> entries;
  std::size_t width = 0;
  for (const Algorithm& name : algorithms) {
    const AlgorithmSpec<double>& spec = algorithm_spec(name);
    for (const auto* list : {&spec.inputs, &spec.outputs})
      for (const ArraySpec& a : *list) {
        if (std::any_of(entries.begin(), entries.end(),
                        [&](const auto& e) { return e.second->name == a.name; }))
          continue;
        entries.emplace_back(fmt::format("{}[{}]", a.name, extent_in(a.extent, dialect)), &a);
        width = std::max(width, entries.back().first.size() + 2);
      }
  }
  std::string text;
  for (const auto& [array, a] : entries) {
    text += fmt::format("///   {:<{}}{}{}\n", array, width, a->meaning,
                        eigen.empty() || !is_matrix(a->extent)
                            ? ""
                            : fmt::format(" (Eigen: {}, not a MatrixXd's data())", eigen));
    if (a->name == "q")
      for (const std::string& line : free_joints)
        text += fmt::format("///   {:<{}}{}\n", "", width, line);
  }
  if (!text.empty()) text.pop_back();
  return text;
}

/// The header's words on the code's structure.
std::string structure_words(Structure structure, const std::vector<FunctionCounts>& counts) {
  const bool lanes = std::any_of(counts.begin(), counts.end(),
                                 [](const FunctionCounts& c) { return c.lane_blocks > 0; });
  const std::string in_lanes =
      lanes ? std::string("repeated limbs computed in lanes of GCC's and clang's vector types") +
                  (structure == Structure::Auto ? ", other " : "")
            : std::string();
  if (structure == Structure::Shared)
    return in_lanes + "repeated link sections call shared functions";
  if (structure == Structure::Auto)
    return in_lanes + "big functions' repeated link sections call shared functions";
  return lanes ? in_lanes : "every link section in place";
}

}  // namespace

/// text as /// comment lines of at most 100 columns, broken at spaces.
std::string comment_lines(const std::string& text) {
  std::string out, line;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find(' ', at), text.size());
    const std::string word = text.substr(at, end - at);
    if (!line.empty() && 4 + line.size() + 1 + word.size() > 100) {
      out += "/// " + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    at = end + 1;
  }
  return line.empty() ? out : out + "/// " + line + "\n";
}

/// The header's line on the rotor inertias built into M, or "" without any.
std::string armature_words(const Model<double>& model) {
  if (model.armature.empty()) return "";
  std::string text;
  const std::vector<std::string> names = velocity_names(model);
  for (std::size_t k = 0; k < names.size(); ++k)
    if (model.armature[k] != 0)
      text += fmt::format("{}{} {}", text.empty() ? "" : ", ", safe_text(names[k]),
                          model.armature[k]);
  return comment_lines("Rotor inertias (armature, kg m^2 or kg) are built into M: " + text + ".");
}

std::map<std::string, std::string> trig_values(const Model<double>& model, const std::string& nq) {
  const std::vector<int> mimics = own_angle_mimics(model);
  if (mimics.empty()) return {{"trig_entries", nq}, {"mimic_trig", ""}};
  std::string text =
      "The entries after q's hold the sine and cosine of the mimic joints' own angles:";
  for (std::size_t j = 0; j < mimics.size(); ++j)
    text +=
        fmt::format("{} [{} + {}] {}", j ? "," : "", nq, j, safe_text(model.joint_name[mimics[j]]));
  return {{"trig_entries", fmt::format("{} + {}", nq, mimics.size())},
          {"mimic_trig", comment_lines(text + ".")}};
}

std::map<std::string, std::string> header_values(const PackageContext& p, const Dialect& dialect,
                                                 const PackageSummary& summary,
                                                 const std::string& frames,
                                                 const std::string& declarations) {
  const Vec3<double>& g = p.model.gravity;
  std::map<std::string, std::string> values = trig_values(p.model, dialect.size("nq"));
  values.insert(
      {{"banner", summary.code_banner},
       {"robot", safe_text(p.robot.name)},
       {"scalar", p.scalar},
       {"sincos", p.single ? "dyngen_sincosf" : "dyngen_sincos"},
       {"structure", structure_words(p.options.structure, summary.counts)},
       {"gravity", fmt::format("({}, {}, {}) m/s^2", g.x, g.y, g.z)},
       {"armature", armature_words(p.model)},
       {"nq", std::to_string(p.model.nq)},
       {"nv", std::to_string(p.model.nv)},
       {"arrays", array_docs(p.options.algorithms, free_joint_lines(p.model), dialect,
                             p.options.language == "c++" ? p.ns + "_eigen.hpp" : "")},
       {"frames", frames},
       {"declarations",
        declarations.empty() ? declarations : declarations.substr(0, declarations.size() - 1)}});
  return values;
}

}  // namespace dyngen::gen
