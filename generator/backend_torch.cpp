// The PyTorch backend: NAME_torch.py beside the Python module, torch.autograd.Functions whose
// backward calls the package's derivative functions, and the configuration space.
#include <algorithm>
#include <array>
#include <functional>

#include <fmt/format.h>

#include "backend.hpp"
#include "names.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

/// The functions NAME_torch.py wraps, in its order, and the package's functions that each
/// one's backward calls (templates/torch_NAME.py.in).
struct TorchFunction {
  const char* name;
  std::vector<const char*> backward;
};

const std::array<TorchFunction, 8>& torch_functions() {
  static const std::array<TorchFunction, 8> functions{{
      {"aba", {"rnea_derivatives", "minv"}},
      {"rnea", {"rnea_derivatives", "crba", "regressor"}},  // regressor: rnea(params=)
      {"crba", {"rnea_derivatives"}},
      {"nle", {"rnea_derivatives"}},
      {"gravity", {"rnea_derivatives"}},
      {"minv", {"rnea_derivatives"}},
      {"frame_placements", {"frame_jacobians"}},
      {"com", {}},
  }};
  return functions;
}

std::string joined(const std::vector<int>& values) {
  return fmt::format("{}", fmt::join(values, ", "));
}

/// (q index, v index) pairs as a Python tuple of tuples.
std::string index_pairs(const std::vector<std::array<int, 2>>& pairs) {
  std::string text;
  for (const auto& [qi, vi] : pairs) text += fmt::format("({}, {}), ", qi, vi);
  return text;
}

/// The bodies in the order of Pinocchio's reader: for URDF depth first from the roots, children
/// in the byte order of their joints' names (urdfdom keeps joints in a map by name); for other
/// formats (MJCF) the file's, which is dyngen's.
std::vector<int> pinocchio_bodies(const Robot& robot, const Model<double>& model) {
  std::vector<int> order;
  if (robot.format != "URDF") {
    for (int i = 0; i < model.nbodies; ++i) order.push_back(i);
    return order;
  }
  std::function<void(int)> visit = [&](int parent) {
    std::vector<int> children;
    for (int i = 0; i < model.nbodies; ++i)
      if (model.parent[i] == parent) children.push_back(i);
    std::sort(children.begin(), children.end(),
              [&](int a, int b) { return model.joint_name[a] < model.joint_name[b]; });
    for (const int c : children) {
      order.push_back(c);
      visit(c);
    }
  };
  visit(-1);
  return order;
}

/// The values of torch.py.in that describe the robot's joints.
void add_joint_values(std::map<std::string, std::string>& values, const Robot& robot,
                      const Model<double>& model) {
  std::vector<int> scalar_q, scalar_v, pin_q, pin_v;
  std::vector<std::array<int, 2>> free, ball;
  for (const int i : pinocchio_bodies(robot, model)) {
    if (is_mimic(model, i)) continue;
    const int qi = model.q_index[i], vi = model.v_index[i];
    const JointType t = model.joint_type[i];
    for (int k = 0; k < joint_nv(t); ++k) pin_v.push_back(vi + k);
    if (t == JointType::Free) {
      free.push_back({qi, vi});
      pin_q.insert(pin_q.end(), {qi, qi + 1, qi + 2, qi + 4, qi + 5, qi + 6, qi + 3});
    } else if (t == JointType::Ball) {
      ball.push_back({qi, vi});
      pin_q.insert(pin_q.end(), {qi + 1, qi + 2, qi + 3, qi});
    } else {
      scalar_q.push_back(qi), scalar_v.push_back(vi);
      pin_q.push_back(qi);
    }
  }
  values["scalar_q"] = joined(scalar_q);
  values["scalar_v"] = joined(scalar_v);
  values["free"] = index_pairs(free);
  values["ball"] = index_pairs(ball);
  values["pinocchio_q"] = joined(pin_q);
  values["pinocchio_v"] = joined(pin_v);
}

class TorchBackend final : public Backend {
 public:
  void add_function(const PackageContext& /*p*/, const TracedFunction& f) override {
    present_.emplace_back(f.spec.name);
  }

  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override {
    auto has = [&](const std::string& name) {
      return std::find(present_.begin(), present_.end(), name) != present_.end();
    };
    std::string functions;
    if (has("crba") || has("minv"))
      functions += fill("torch_mass_matrix.py.in",
                        {{"users", has("crba") && has("minv") ? "crba and minv"
                                   : has("crba")              ? "crba"
                                                              : "minv"}});
    for (const TorchFunction& f : torch_functions())
      if (has(f.name))
        functions += fill(fmt::format("torch_{}.py.in", f.name), {{"name", f.name}});
    std::map<std::string, std::string> values{{"banner", summary.hash_banner},
                                              {"name", p.ns},
                                              {"dtype", p.single ? "float32" : "float64"},
                                              {"functions", functions}};
    add_joint_values(values, p.robot, p.model);
    files.push_back({p.ns + "_torch.py", fill("torch.py.in", values)});
  }

  void add_cmake_values(std::map<std::string, std::string>& values,
                        const PackageContext& p) const override {
    values["targets"] += fill("torch.cmake.in", {{"name", p.ns}, {"NAME", upper(p.ns)}});
  }

 private:
  std::vector<std::string> present_;
};

}  // namespace

std::vector<Algorithm> with_torch_backwards(const std::vector<Algorithm>& listed,
                                            const std::vector<Algorithm>& known) {
  std::vector<Algorithm> chosen = listed;
  for (const TorchFunction& f : torch_functions())
    if (std::find(listed.begin(), listed.end(), f.name) != listed.end())
      chosen.insert(chosen.end(), f.backward.begin(), f.backward.end());
  std::vector<Algorithm> out;
  for (const Algorithm& a : known)
    if (std::find(chosen.begin(), chosen.end(), a) != chosen.end()) out.push_back(a);
  return out;
}

std::vector<Algorithm> torch_default_algorithms() {
  std::vector<Algorithm> names;
  for (const TorchFunction& f : torch_functions()) names.emplace_back(f.name);
  return names;
}

std::unique_ptr<Backend> make_torch_backend(const GenerateOptions& /*options*/) {
  return std::make_unique<TorchBackend>();
}

}  // namespace dyngen::gen
