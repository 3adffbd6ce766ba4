// The Eigen backend: NAME_eigen.hpp, the C++ functions over Eigen's fixed-size types with the
// layouts their arrays have (issue 46: a column-major matrix's data() would give the transpose).
// It prints no program: each overload passes its matrices' data() to the plain function.
#include <fmt/format.h>

#include "backend.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

/// The size's name in the package's header: nq, nv, nc.
std::string size_name(Extent::Size s) {
  switch (s) {
    case Extent::Nq: return "nq";
    case Extent::Nv:
    case Extent::NvNv:
    case Extent::NcNv: return "nv";
    case Extent::Nc: return "nc";
    case Extent::One: return "1";
  }
  return "1";
}

/// The rows and columns of one state's (one frame's) entries of an array.
std::pair<std::string, std::string> shape(const Extent& e) {
  if (e.per_body)  // nv rows of count entries per body: the regressor's Y
    return {"nv", fmt::format("nbodies * {}", e.count)};
  if (e.size == Extent::NvNv || e.size == Extent::NcNv) {
    const char* rows = e.size == Extent::NvNv ? "nv" : "nc";
    return {e.count > 1 ? fmt::format("{} * {}", e.count, rows) : rows, "nv"};
  }
  if (e.count == 9) return {"3", "3"};  // a rotation, row-major
  if (e.size == Extent::One) return {fmt::format("{}", e.count), "1"};
  if (e.count > 1) return {fmt::format("{}", e.count), size_name(e.size)};  // a Jacobian
  return {size_name(e.size), "1"};
}

/// An array's Eigen type: eigen::Matrix<rows, cols>, or eigen::PerFrame<rows, cols, nframes>.
std::string eigen_type(const Extent& e) {
  const auto [rows, cols] = shape(e);
  return e.per_frame ? fmt::format("eigen::PerFrame<{}, {}, nframes>", rows, cols)
                     : fmt::format("eigen::Matrix<{}, {}>", rows, cols);
}

/// The overload of one function: inputs by const reference (any Eigen expression of the size
/// converts), outputs by reference to exactly their type.
std::string eigen_function(const AlgorithmSpec<double>& spec) {
  std::vector<std::string> parameters, arguments;
  for (const ArraySpec& a : spec.inputs) {
    parameters.push_back(fmt::format("const {}& {}", eigen_type(a.extent), a.name));
    arguments.push_back(fmt::format("{}.data(){}", a.name, a.extent.per_frame ? "->data()" : ""));
  }
  for (const ArraySpec& a : spec.outputs) {
    parameters.push_back(fmt::format("{}& {}", eigen_type(a.extent), a.name));
    arguments.push_back(a.extent.per_frame ? fmt::format("{}[0].data()", a.name)
                                           : fmt::format("{}.data()", a.name));
  }
  const std::string text =
      wrapped_parameters(fmt::format("inline void {}(", spec.name), parameters, ") noexcept {");
  std::string call;
  for (const std::string& a : arguments) call += (call.empty() ? "" : ", ") + a;
  return fmt::format("\n/// {}\n{}\n    {}({});\n}}\n", spec.summary, text, spec.name, call);
}

class EigenBackend final : public Backend {
 public:
  void add_function(const PackageContext& /*p*/, const TracedFunction& f) override {
    functions_ += eigen_function(f.spec);
  }

  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override {
    files.push_back({p.ns + "_eigen.hpp", fill("eigen.hpp.in", {{"banner", summary.code_banner},
                                                                {"name", p.ns},
                                                                {"namespace", p.ns},
                                                                {"scalar", p.scalar},
                                                                {"functions", functions_}})});
  }

 private:
  std::string functions_;
};

}  // namespace

std::unique_ptr<Backend> make_eigen_backend(const GenerateOptions& /*options*/) {
  return std::make_unique<EigenBackend>();
}

}  // namespace dyngen::gen
