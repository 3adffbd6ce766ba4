// The Python backend: a pybind11 module over the batch functions (NAME_python.cpp), taking and
// returning NumPy arrays of one state, shape (n,), or of N, shape (N, n).
#include <fmt/format.h>

#include "backend.hpp"
#include "names.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

/// The NumPy shape of one state's entries of an array, as a C++ initialiser over the package's
/// constants: {::ur5::nframes, 3, 3} for a rotation per frame, {::ur5::nv, ::ur5::nv} for M.
std::string python_shape(const Extent& e, const std::string& ns) {
  const std::string scope = "::" + ns + "::";
  std::vector<std::string> dims;
  if (e.per_body)  // nv rows of count entries per body: the regressor's Y
    return fmt::format("{{{0}nv, {0}nbodies * {1}}}", scope, e.count);
  if (e.per_frame) dims.push_back(scope + "nframes");
  if (e.count == 9)  // a rotation, row-major
    dims.insert(dims.end(), {"3", "3"});
  else if (e.count > 1)
    dims.push_back(std::to_string(e.count));
  if (e.size == Extent::Nq) dims.push_back(scope + "nq");
  if (e.size == Extent::Nv) dims.push_back(scope + "nv");
  if (e.size == Extent::NvNv) dims.insert(dims.end(), {scope + "nv", scope + "nv"});
  if (e.size == Extent::Nc) dims.push_back(scope + "nc");
  if (e.size == Extent::NcNv) dims.insert(dims.end(), {scope + "nc", scope + "nv"});
  std::string text;
  for (const std::string& d : dims) text += (text.empty() ? "" : ", ") + d;
  return "{" + text + "}";
}

/// The shapes of an array for one and for N states, in words for a docstring: "(nv,) or (N,
/// nv)", "(nframes, 3, 3) or (N, nframes, 3, 3)".
std::string python_shape_words(const Extent& e, const std::string& ns) {
  const std::string scope = "::" + ns + "::";
  std::string dims = python_shape(e, ns);
  for (std::size_t at; (at = dims.find(scope)) != std::string::npos;) dims.erase(at, scope.size());
  dims = dims.substr(1, dims.size() - 2);
  return fmt::format("({}{}) or (N, {})", dims, dims.find(',') == std::string::npos ? "," : "",
                     dims);
}

/// One function's m.def in the Python module (python_function.cpp.in).
std::string python_function(const AlgorithmSpec<double>& spec, const std::string& ns) {
  std::string parameters, input_arguments, output_arguments, pointers, arguments, keywords, doc;
  for (std::size_t k = 0; k < spec.inputs.size(); ++k) {
    const ArraySpec& a = spec.inputs[k];
    parameters += fmt::format("{}const py::array& {}", k ? ", " : "", a.name);
    input_arguments += fmt::format("{}{{\"{}\", {}}}", k ? ", " : "", a.name,
                                   python_shape(a.extent, ns));
    pointers += fmt::format("{}x[{}]", k ? ", " : "", k);
    arguments += fmt::format("{}&{}", k ? ", " : "", a.name);
    keywords += fmt::format("{}py::arg(\"{}\")", k ? ", " : "", a.name);
    doc += fmt::format("\n{}: {}, {}", a.name, python_shape_words(a.extent, ns), a.meaning);
  }
  doc += spec.outputs.size() == 1 ? "\nReturns" : "\nReturns a tuple of";
  for (std::size_t k = 0; k < spec.outputs.size(); ++k) {
    const ArraySpec& a = spec.outputs[k];
    output_arguments += fmt::format("{}{{\"{}\", {}}}", k ? ", " : "", a.name,
                                    python_shape(a.extent, ns));
    pointers += fmt::format(", y[{}]", k);
    doc += fmt::format("{}\n{}: {}, {}", k ? "," : ":", a.name, python_shape_words(a.extent, ns),
                       a.meaning);
  }
  return fill("python_function.cpp.in",
              {{"name", std::string(spec.name)},
               {"namespace", ns},
               {"parameters", parameters},
               {"inputs", std::to_string(spec.inputs.size())},
               {"outputs", std::to_string(spec.outputs.size())},
               {"input_arguments", input_arguments},
               {"output_arguments", output_arguments},
               {"pointers", pointers},
               {"arguments", arguments},
               {"keywords", keywords},
               {"doc", python_literal(std::string(spec.summary) + "\n" + doc)}});
}

/// A list of names for the Python module: str_list({"a", "b"}) with python_literal's literals.
std::string python_names(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + python_literal(name);
  return "str_list({" + list + "})";
}

/// The Python module's constants beyond nq, nv, lanes and dtype.
/// The module's to_pinocchio_q, from_pinocchio_q, to_pinocchio_v and from_pinocchio_v (tuples of
/// indices, pinocchio_maps), or None each, with the reason in a comment.
std::string python_pinocchio(const Robot& robot, const Model<double>& model) {
  const PinocchioMaps maps = pinocchio_maps(robot, model);
  const char* names[] = {"to_pinocchio_q", "from_pinocchio_q", "to_pinocchio_v",
                         "from_pinocchio_v"};
  const std::vector<int>* lists[] = {&maps.to_q, &maps.from_q, &maps.to_v, &maps.from_v};
  std::string text =
      "    // Pinocchio's coordinates (README, \"Coordinates beside Pinocchio's\"): "
      "q_pinocchio = q[..., to_pinocchio_q]\n";
  if (!maps.missing.empty()) text += "    // none: " + maps.missing + "\n";
  for (int k = 0; k < 4; ++k)
    text += fmt::format("    m.attr(\"{}\") = {};\n", names[k],
                        maps.missing.empty()
                            ? fmt::format("py::make_tuple({})", fmt::join(*lists[k], ", "))
                            : std::string("py::none()"));
  return text;
}

std::string python_attributes(const Model<double>& model) {
  const Vec3<double>& g = model.gravity;
  double mass = 0;
  std::string quaternions;
  for (int i = 0; i < model.nbodies; ++i) {
    mass += model.I[i].m;
    if (const int o = quaternion_offset(model.joint_type[i]); o >= 0)
      quaternions += fmt::format("{}{}", quaternions.empty() ? "" : ", ", model.q_index[i] + o);
  }
  std::string armature;
  for (int k = 0; k < model.nv; ++k)
    armature += (k ? ", " : "") + literal(model.armature.empty() ? 0.0 : model.armature[k]);
  std::string text = fmt::format(
      "    m.attr(\"joint_names\") = {};\n"
      "    m.attr(\"gravity_acceleration\") = py::make_tuple({}, {}, {});  // m/s^2\n"
      "    m.attr(\"total_mass\") = {};\n"
      "    // rotor inertia built into M's diagonal, per entry of v (kg m^2 or kg)\n"
      "    m.attr(\"armature\") = py::make_tuple({});\n"
      "    // q[k:k + 4] is a free or ball joint's unit quaternion (w, x, y, z) for each k\n"
      "    m.attr(\"quaternion_indices\") = py::make_tuple({});\n",
      python_names(velocity_names(model)), literal(g.x), literal(g.y), literal(g.z), literal(mass),
      armature, quaternions);
  std::vector<std::string> frames;
  for (const Frame<double>& f : model.frames) frames.push_back(f.name);
  if (!frames.empty())
    text += fmt::format("    m.attr(\"frame_names\") = {};\n", python_names(frames));
  std::vector<std::string> constraints;
  for (const Constraint<double>& c : model.constraints) constraints.push_back(c.name);
  if (!constraints.empty())
    text += fmt::format(
        "    // the constraints (--contacts, loops): lambda's 3 entries per :3d, 6 per :6d\n"
        "    m.attr(\"constraint_names\") = {};\n    m.attr(\"nc\") = {};\n",
        python_names(constraints), model.nc);
  // the bodies' standard parameters (dyngen/regressor.hpp), (nbodies, 10): tau = Y pi + ...
  std::string pi;
  for (int i = 0; i < model.nbodies; ++i) {
    double p[parameters_per_body];
    inertial_parameters(model.I[i], p);
    pi += "\n        ";
    for (const double x : p) pi += literal(x) + ", ";
  }
  text += fmt::format(
      "    m.attr(\"body_names\") = {};\n"
      "    // each body's standard parameters: m, m c, Ixx, Ixy, Iyy, Ixz, Iyz, Izz about its origin\n"
      "    static const Scalar parameters[] = {{{}}};\n"
      "    m.attr(\"inertial_parameters\") = py::array_t<Scalar>(\n"
      "        std::vector<py::ssize_t>{{{}, {}}}, parameters);\n",
      python_names(model.body_name), pi, model.nbodies, parameters_per_body);
  return text;
}

class PythonBackend final : public Backend {
 public:
  void add_function(const PackageContext& p, const TracedFunction& f) override {
    functions_ += python_function(f.spec, p.ns);
  }

  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override {
    files.push_back({p.ns + "_python.cpp",
                     fill("python.cpp.in", {{"banner", summary.code_banner},
                                            {"name", p.ns},
                                            {"namespace", p.ns},
                                            {"robot", python_literal(p.robot.name)},
                                            {"scalar", p.scalar},
                                            {"dtype", p.single ? "float32" : "float64"},
                                            {"lanes", std::to_string(p.options.batch)},
                                            {"attributes", python_attributes(p.model) +
                                                               python_pinocchio(p.robot, p.model)},
                                            {"functions", functions_}})});
    // pip install: the module built by the package's CMakeLists.txt
    files.push_back({"pyproject.toml", fill("pyproject.toml.in", {{"banner", summary.hash_banner},
                                                                  {"name", p.ns},
                                                                  {"version", version}})});
    files.push_back({"setup.py", fill("setup.py.in", {{"banner", summary.hash_banner},
                                                      {"name", p.ns},
                                                      {"NAME", upper(p.ns)}})});
  }

  void add_cmake_values(std::map<std::string, std::string>& values,
                        const PackageContext& p) const override {
    values["targets"] += fill("python_module.cmake.in", {{"name", p.ns}, {"NAME", upper(p.ns)}});
  }

 private:
  std::string functions_;
};

}  // namespace

std::unique_ptr<Backend> make_python_backend(const GenerateOptions& options) {
  if (options.language != "c++")
    throw InputError("--python: batch functions are C++ (GCC's and clang's vector types); "
                     "generate them with --lang c++");
  return std::make_unique<PythonBackend>();
}

}  // namespace dyngen::gen
