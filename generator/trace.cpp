#include "trace.hpp"

#include <cmath>
#include <span>

#include "dyngen/aba.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/rnea.hpp"

namespace dyngen::gen {

const char* algorithm_name(Algorithm a) {
  switch (a) {
    case Algorithm::Rnea: return "rnea";
    case Algorithm::Crba: return "crba";
    case Algorithm::Aba: return "aba";
  }
  return "?";
}

template <class T>
Program<T> trace(Algorithm algorithm, const Model<double>& model, bool simplify) {
  Program<T> program;
  program.algorithm = algorithm;
  program.graph = Graph<T>(simplify);
  Graph<T>& g = program.graph;
  const Recording<T> recording(g);
  // the same conversion the check harness applies: double -> T -> constant nodes
  const Model<Sym<T>> m = model.cast<T>().template cast<Sym<T>>();
  Workspace<Sym<T>> ws(m);
  const int n = model.nv;
  auto inputs = [&](const char* name, int size) {
    program.input_arrays.push_back(name);
    std::vector<Sym<T>> x;
    for (int i = 0; i < size; ++i) x.push_back(Sym<T>::node(g.input(name, i)));
    return x;
  };
  std::vector<Sym<T>> out;
  switch (algorithm) {
    case Algorithm::Rnea: {
      const auto q = inputs("q", model.nq), v = inputs("v", n), a = inputs("a", n);
      out.resize(n);
      rnea<Sym<T>>(m, ws, q, v, a, out);
      program.output_array = "tau";
      break;
    }
    case Algorithm::Crba: {
      const auto q = inputs("q", model.nq);
      out.resize(static_cast<std::size_t>(n) * n);
      crba<Sym<T>>(m, ws, q, out);
      program.output_array = "M";
      break;
    }
    case Algorithm::Aba: {
      const auto q = inputs("q", model.nq), v = inputs("v", n), tau = inputs("tau", n);
      out.resize(n);
      aba<Sym<T>>(m, ws, q, v, tau, out);
      program.output_array = "qdd";
      break;
    }
  }
  program.output_size = static_cast<int>(out.size());
  for (const Sym<T>& s : out) program.outputs.push_back(s.id);
  return program;
}

template <class T>
int first_non_finite_constant(const Program<T>& program) {
  const auto& nodes = program.graph.nodes;
  std::vector<bool> live(nodes.size(), false);
  for (const int id : program.outputs) live[id] = true;
  int first = -1;
  for (int id = static_cast<int>(nodes.size()) - 1; id >= 0; --id) {
    if (!live[id]) continue;
    if (nodes[id].op == Op::Const && !std::isfinite(nodes[id].value)) first = id;
    if (nodes[id].a >= 0) live[nodes[id].a] = true;
    if (nodes[id].b >= 0) live[nodes[id].b] = true;
  }
  return first;
}

template int first_non_finite_constant<double>(const Program<double>&);
template int first_non_finite_constant<float>(const Program<float>&);
template Program<double> trace<double>(Algorithm, const Model<double>&, bool);
template Program<float> trace<float>(Algorithm, const Model<double>&, bool);

}  // namespace dyngen::gen
