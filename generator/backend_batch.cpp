// The batch backend: f_batch computes `lanes` states at once, each value a vector of GCC's and
// clang's vector types (C++), and f_many any count of states over it. Inputs and outputs hold
// entry i of state l at [i * lanes + l]. Every lane performs the scalar code's operations, so
// the bits are the scalar code's.
#include <fmt/format.h>

#include "backend.hpp"
#include "names.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace {

/// The parameters of f_many: the count, then the arrays of count states each.
std::vector<std::string> many_parameters(const AlgorithmSpec<double>& spec,
                                         const std::string& scalar) {
  std::vector<std::string> out{"long count"};
  for (const ArraySpec& a : spec.inputs) out.push_back(fmt::format("const {}* {}", scalar, a.name));
  for (const ArraySpec& a : spec.outputs) out.push_back(fmt::format("{}* {}", scalar, a.name));
  return out;
}

/// f_many's body in many.cpp.in: each batch's arrays gathered into lanes (gather), f_batch's
/// arguments, and its outputs scattered back (scatter).
std::map<std::string, std::string> many_values(const AlgorithmSpec<double>& spec,
                                               const std::string& scalar, const Dialect& dialect) {
  std::string gather, scatter, arguments;
  for (const auto* list : {&spec.inputs, &spec.outputs})
    for (const ArraySpec& a : *list) {
      const std::string n = extent_in(a.extent, dialect);
      gather += fmt::format("        {} {}_lanes[{} * lanes];\n", scalar, a.name, n);
      if (list == &spec.inputs)
        gather += fmt::format("        to_lanes<{}>({}, first, count, {}_lanes);\n", n, a.name,
                              a.name);
      else
        scatter += fmt::format("        from_lanes<{}>({}_lanes, first, count, {});\n", n,
                               a.name, a.name);
      arguments += fmt::format("{}{}_lanes", arguments.empty() ? "" : ", ", a.name);
    }
  return {{"gather", gather}, {"scatter", scatter}, {"arguments", arguments}};
}

class BatchBackend final : public Backend, public Dialect {
 public:
  explicit BatchBackend(const GenerateOptions& options)
      : Dialect(options.name), lanes_(options.batch) {}

  const Dialect* dialect() const override { return this; }

  // ---- Dialect: names
  std::string function(const std::string& a) const override { return a + "_batch"; }
  std::string joint_trig() const override { return "joint_trig_batch"; }
  std::string trig_type() const override { return "JointTrigBatch"; }

  // ---- Dialect: statements, over lanes
  int lanes() const override { return lanes_; }
  bool lane_blocks() const override { return false; }
  std::string value_type(const std::string& /*scalar*/) const override { return "lane"; }
  /// An input's entry, loaded into lanes first (load): "q3".
  std::string input(const std::string& array, int index) const override {
    return array + std::to_string(index);
  }
  std::string trig_value(const char* function, int index) const override {
    return fmt::format("{}_q{}", function, index);
  }
  /// Lane by lane: "lane{f(x[0]), f(x[1])}" (a function of vectors would pass them in
  /// registers that differ with the instruction set, which GCC warns of).
  std::string function_call(const std::string& function,
                            const std::vector<std::string>& arguments) const override {
    std::string out = "lane{";
    for (int l = 0; l < lanes_; ++l) {
      std::string items;
      for (const std::string& a : arguments)
        items += fmt::format("{}{}[{}]", items.empty() ? "" : ", ", a, l);
      out += fmt::format("{}{}({})", l ? ", " : "", function, items);
    }
    return out + "}";
  }
  /// A constant fills every lane.
  std::string element(const std::string& constant) const override {
    std::string copies = constant;
    for (int l = 1; l < lanes_; ++l) copies += ", " + constant;
    return "lane{" + copies + "}";
  }
  std::string store(std::string_view array, std::size_t k,
                    const std::string& value) const override {
    return fmt::format("    store({} + {} * lanes, {});\n", array, k, value);
  }
  std::string entry(std::size_t k) const override {
    return k == 0 ? "0" : fmt::format("{} * lanes", k);
  }
  std::string load(const std::vector<Read>& reads) const override {
    if (reads.empty()) return "";
    std::string out = "    // the inputs' lanes\n";
    for (const Read& r : reads)
      out += fmt::format("    lane {}; load({}, {} + {} * lanes);\n", r.value, r.value, r.from,
                         r.index);
    return out + "\n";
  }
  std::string kernel_call(const KernelRecord& call, std::vector<std::string> arguments,
                          const std::string& kernel, const std::string& scalar) const override;
  /// One call for a run's lanes too.
  std::string sincos_run(int first, int count, const char* sincos,
                         const std::string& trig) const override {
    return fmt::format(
        "    {3}_array(q + {0} * lanes, {4}sin_q + {0} * lanes, {4}cos_q + {0} * lanes, {1} * "
        "lanes);  // q[{0}..{2}]\n",
        first, count, first + count - 1, sincos, trig);
  }

  std::string q_entry(int k) const override { return fmt::format("q[{} * lanes + l]", k); }
  std::string sincos_angle(int k, const std::string& angle, const char* sincos,
                           const std::string& trig, const std::string& what) const override {
    return fmt::format(
        "    for (int l = 0; l < lanes; ++l)  // {4}\n"
        "        {0}({1}, &{2}sin_q[{3} * lanes + l], &{2}cos_q[{3} * lanes + l]);\n",
        sincos, angle, trig, k, what);
  }

  // ---- Backend
  void add_function(const PackageContext& p, const TracedFunction& f) override;

  std::string check_case(const PackageContext& p, const TracedFunction& f) const override {
    const std::string a(f.spec.name);
    return fill("batch_check.cpp.in", {{"name", a},
                                       {"namespace", p.ns},
                                       {"call", "::" + p.ns + "::" + a},
                                       {"arguments", call_arguments(f.spec, *this).first}});
  }

  std::string check_include(const PackageContext& p) const override {
    return fmt::format("#include \"{}_batch.hpp\"\n", p.ns);
  }

  void add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                 const PackageSummary& summary) const override;

  void add_cmake_values(std::map<std::string, std::string>& values,
                        const PackageContext& p) const override {
    values["sources"] += fmt::format(" {}_batch.cpp", p.ns);
  }

 private:
  int lanes_;
  std::string declarations_, definitions_;
};

/// A kernel call lane by lane: each state's numbers copied out of the lanes, the scalar
/// kernel, and its results copied back.
std::string BatchBackend::kernel_call(const KernelRecord& call, std::vector<std::string> arguments,
                                      const std::string& kernel, const std::string& scalar) const {
  const std::size_t first_array = call.ints.size() + call.tables.size();
  const std::size_t arrays = call.inputs.size() + call.outputs.size();
  std::string declare, copy_in, copy_out;
  for (std::size_t j = 0; j < arrays; ++j) {
    const bool input = j < call.inputs.size();
    const std::string& array = arguments[first_array + j];
    const std::size_t size = input ? call.inputs[j].size() : call.outputs[j - call.inputs.size()];
    declare += fmt::format("        {} {}_l[{}];\n", scalar, array, size);
    if (input)
      copy_in += fmt::format("        for (int k = 0; k < {1}; ++k) {0}_l[k] = {0}[k][l];\n",
                             array, size);
    else
      copy_out += fmt::format("        for (int k = 0; k < {1}; ++k) {0}[k][l] = {0}_l[k];\n",
                              array, size);
    arguments[first_array + j] = array + "_l";
  }
  return "    for (int l = 0; l < lanes; ++l) {\n" + declare + copy_in +
         wrapped_call(kernel, arguments, "        ") + copy_out + "    }\n";
}

/// f_batch and f_many: the same program printed over lanes, and the function over any count
/// of states. A batch runs its states in the lanes, so only the kernel calls that keep the
/// code small stay.
void BatchBackend::add_function(const PackageContext& p, const TracedFunction& f) {
  const std::string a(f.spec.name), summary(f.spec.summary);
  if (p.options.progress) p.options.progress(fmt::format("printing {} for batches of {}", a, lanes_));
  const auto [code, counts] = f.print(*this, false);
  const std::string many_call = declaration(a + "_many", many_parameters(f.spec, p.scalar), *this);
  declarations_ +=
      fill("batch_function.hpp.in",
           {{"summary", summary},
            {"lanes", std::to_string(lanes_)},
            {"batch_declaration",
             declaration(function(a), parameters(f.spec, p.scalar, false, *this), *this)},
            {"trig_declaration",
             declaration(function(a) + "_trig", parameters(f.spec, p.scalar, true, *this), *this)},
            {"many_declaration", many_call}}) +
      "\n";
  definitions_ += function_definitions(p, *this, f.spec, code, summary + " (a batch)",
                                       to_string(counts) + " per lane");
  std::map<std::string, std::string> many = many_values(f.spec, p.scalar, *this);
  many.insert({{"summary", summary}, {"declaration", many_call}, {"batch", function(a)}});
  definitions_ += fill("many.cpp.in", many);
}

void BatchBackend::add_files(std::vector<GeneratedFile>& files, const PackageContext& p,
                             const PackageSummary& summary) const {
  const std::map<std::string, std::string> values{{"banner", summary.code_banner},
                                                  {"name", p.ns},
                                                  {"namespace", p.ns},
                                                  {"scalar", p.scalar},
                                                  {"lanes", std::to_string(lanes_)}};
  std::map<std::string, std::string> h = values, cpp = values;
  h.merge(trig_values(p.model, "nq"));
  if (h["trig_entries"] != "nq") h["trig_entries"] = "(" + h["trig_entries"] + ")";
  h.insert({{"robot", safe_text(p.robot.name)},
            {"sincos", p.single ? "dyngen_sincosf" : "dyngen_sincos"},
            {"declarations", declarations_.substr(0, declarations_.size() - 1)}});
  cpp.insert({{"floating_point", floating_point_lines(p.ns + "_batch.cpp")},
              {"joint_trig", emit_joint_trig(p.model, p.single, *this)},
              {"support_includes", summary.support_includes()},
              {"definitions", definitions_}});
  files.push_back({p.ns + "_batch.hpp", fill("batch.hpp.in", h)});
  files.push_back({p.ns + "_batch.cpp", fill("batch.cpp.in", cpp)});
}

}  // namespace

std::unique_ptr<Backend> make_batch_backend(const GenerateOptions& options) {
  if (options.language != "c++")
    throw InputError("--batch: batch functions are C++ (GCC's and clang's vector types); "
                     "generate them with --lang c++");
  return std::make_unique<BatchBackend>(options);
}

}  // namespace dyngen::gen
