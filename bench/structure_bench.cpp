// The code structures side by side (bench/structure_bench.sh): each robot's rnea, crba, aba,
// frame_accelerations and centroidal as dyngen writes them with --structure unrolled, shared,
// lanes and auto, timed in one binary after each has been checked to return the bits of the
// unrolled code at one state. packages.hpp (written by the script) includes the packages and
// lists them as ROBOT(name, u, s, l, a), the namespaces of the four structures.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "packages.hpp"

namespace {

template <int nq, int nv, int nframes>
struct State {
  double q[nq], v[nv], a[nv];
  State() {
    for (int i = 0; i < nq; ++i) q[i] = 0.3 * std::sin(1.0 + i);
    for (int i = 0; i < nv; ++i) v[i] = 0.5 * std::cos(2.0 + i), a[i] = 0.2 * std::sin(3.0 * i);
  }
};

// The five functions of one package, each writing into out (big enough for any of them).
#define CALLS(ns)                                                                          \
  [](const double* q, const double* v, const double* a, double* out, int f) {             \
    switch (f) {                                                                           \
      case 0: ns::rnea(q, v, a, out); break;                                               \
      case 1: ns::crba(q, out); break;                                                     \
      case 2: ns::aba(q, v, a, out); break;                                                \
      case 3: ns::frame_accelerations(q, v, out); break;                                   \
      default: ns::centroidal(q, v, out, out + 6 * ns::nv); break;                         \
    }                                                                                      \
  }

using Call = void (*)(const double*, const double*, const double*, double*, int);
const char* const functions[] = {"rnea", "crba", "aba", "frame_accelerations", "centroidal"};
const char* const structures[] = {"unrolled", "shared", "lanes", "auto"};

template <int nq, int nv, int nframes>
void add_robot(const char* robot, const Call (&calls)[4]) {
  static State<nq, nv, nframes> state;
  constexpr int size = 7 * nv * nv + 6 * nframes + 64;
  for (int f = 0; f < 5; ++f) {
    static double reference[size];
    std::memset(reference, 0, sizeof reference);
    calls[0](state.q, state.v, state.a, reference, f);
    for (int s = 1; s < 4; ++s) {
      double out[size] = {};
      calls[s](state.q, state.v, state.a, out, f);
      if (std::memcmp(out, reference, sizeof out) != 0) {
        std::fprintf(stderr, "%s %s: --structure %s differs from unrolled\n", robot, functions[f],
                     structures[s]);
        std::exit(1);
      }
    }
    for (int s = 0; s < 4; ++s) {
      const Call call = calls[s];
      benchmark::RegisterBenchmark(
          (std::string(robot) + "/" + functions[f] + "/" + structures[s]).c_str(),
          [call, f](benchmark::State& st) {
            double out[size];
            for (auto _ : st) {
              call(state.q, state.v, state.a, out, f);
              benchmark::DoNotOptimize(out);
              benchmark::ClobberMemory();
            }
          });
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
#define ROBOT(name, u, s, l, a)                                            \
  {                                                                        \
    const Call calls[4] = {CALLS(u), CALLS(s), CALLS(l), CALLS(a)};        \
    add_robot<u::nq, u::nv, u::nframes>(name, calls);                      \
  }
  ROBOTS
  std::printf("every structure returns the unrolled code's bits at one state; timing\n");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
