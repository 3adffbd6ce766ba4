#include "trace.hpp"

#include <cmath>
#include <span>
#include <stdexcept>

namespace dyngen::gen {

std::string extent_text(const Extent& e, const std::string& nq, const std::string& nv,
                        const std::string& nframes, const std::string& nbodies,
                        const std::string& nc) {
  std::vector<std::string> factors;
  if (e.per_frame) factors.push_back(nframes);
  if (e.per_body) factors.push_back(nbodies);
  if (e.count != 1 || e.size == Extent::One) factors.push_back(std::to_string(e.count));
  if (e.size == Extent::Nq) factors.push_back(nq);
  if (e.size == Extent::Nv) factors.push_back(nv);
  if (e.size == Extent::NvNv) factors.insert(factors.end(), {nv, nv});
  if (e.size == Extent::Nc) factors.push_back(nc);
  if (e.size == Extent::NcNv) factors.insert(factors.end(), {nc, nv});
  std::string text;
  for (const std::string& f : factors) text += (text.empty() ? "" : " * ") + f;
  return text;
}

std::vector<Algorithm> algorithm_names() {
  std::vector<Algorithm> names;
  for (const AlgorithmSpec<double>& a : algorithm_table<double>()) names.emplace_back(a.name);
  return names;
}

std::vector<Algorithm> default_algorithm_names() {
  std::vector<Algorithm> names;
  for (const AlgorithmSpec<double>& a : algorithm_table<double>())
    if (a.in_default_set) names.emplace_back(a.name);
  return names;
}

const AlgorithmSpec<double>& algorithm_spec(const Algorithm& name) {
  const AlgorithmSpec<double>* spec = find_algorithm<double>(name);
  if (!spec) throw std::invalid_argument("no algorithm named '" + name + "'");
  return *spec;
}

template <class T>
Program<T> trace(const Algorithm& algorithm, const Model<double>& model, bool simplify,
                 long call_kernels_from, bool vector_kernels) {
  const AlgorithmSpec<Sym<T>>* spec = find_algorithm<Sym<T>>(algorithm);
  if (!spec) throw std::invalid_argument("no algorithm named '" + algorithm + "'");
  Program<T> program;
  program.algorithm = algorithm;
  program.graph = Graph<T>(simplify);
  Graph<T>& g = program.graph;
  g.call_kernels_from = call_kernels_from;
  g.vector_kernels = vector_kernels;
  const Recording<T> recording(g);
  // the same conversion the check harness applies: double -> T -> constant nodes
  const Model<Sym<T>> m = model.cast<T>().template cast<Sym<T>>();
  Workspace<Sym<T>> ws(m);
  const auto size = [&](const ArraySpec& a) { return extent_size(a.extent, model); };

  std::vector<std::vector<Sym<T>>> in, out;
  for (const ArraySpec& a : spec->inputs) {
    program.inputs.push_back({a, size(a)});
    const std::string name(a.name);
    std::vector<Sym<T>>& x = in.emplace_back();
    for (std::size_t k = 0; k < size(a); ++k)
      x.push_back(Sym<T>::node(g.input(name, static_cast<int>(k))));
  }
  for (const ArraySpec& a : spec->outputs) {
    program.outputs.push_back({a, size(a)});
    out.emplace_back(size(a));
  }
  std::vector<std::span<const Sym<T>>> in_spans(in.begin(), in.end());
  std::vector<std::span<Sym<T>>> out_spans(out.begin(), out.end());
  spec->call(m, ws, in_spans, out_spans);
  for (const std::vector<Sym<T>>& y : out)
    for (const Sym<T>& s : y) program.stored.push_back(s.id);
  // the mimic joints' own angles, by the runtime's operations: the same nodes as the trace's
  for (std::size_t k = 0; k < in.size(); ++k)
    if (spec->inputs[k].name == std::string_view("q"))
      for (const int i : own_angle_mimics(model))
        program.mimic_angles.push_back(joint_position(m, i, in[k][m.q_index[i]]).id);
  return program;
}

std::vector<int> own_angle_mimics(const Model<double>& model) {
  std::vector<int> bodies;
  for (int i = 0; i < model.nbodies; ++i)
    if (has_own_angle(model, i)) bodies.push_back(i);
  return bodies;
}

template <class T>
int first_non_finite_constant(const Program<T>& program) {
  const auto& nodes = program.graph.nodes;
  std::vector<bool> live(nodes.size(), false);
  for (const int id : program.stored) live[id] = true;
  int first = -1;
  for (int id = static_cast<int>(nodes.size()) - 1; id >= 0; --id) {
    if (!live[id]) continue;
    if (nodes[id].op == Op::Const && !std::isfinite(nodes[id].value)) first = id;
    program.graph.for_each_operand(id, [&](int x) { live[x] = true; });
  }
  return first;
}

template int first_non_finite_constant<double>(const Program<double>&);
template int first_non_finite_constant<float>(const Program<float>&);
template Program<double> trace<double>(const Algorithm&, const Model<double>&, bool, long, bool);
template Program<float> trace<float>(const Algorithm&, const Model<double>&, bool, long, bool);

}  // namespace dyngen::gen
