// Forward dynamics through the generated CRBA and RNEA and Eigen's LDL^T, in double and float,
// compiled with the generated code's exact-math flags.
#include <dyngen/numerics/ldlt.hpp>

#include "dyngen/report/harness.hpp"

namespace dyngen_report {

template <class S>
void ldlt_forward_dynamics(int nv, CrbaFunction<S> crba, RneaFunction<S> rnea, const S* q,
                           const S* v, const S* tau, S* qdd) {
  static dyngen::numerics::LdltForwardDynamics<S> solve(nv);  // one robot per process
  solve(crba, rnea, q, v, tau, qdd);
}

template void ldlt_forward_dynamics<double>(int, CrbaFunction<double>, RneaFunction<double>,
                                            const double*, const double*, const double*,
                                            double*);
template void ldlt_forward_dynamics<float>(int, CrbaFunction<float>, RneaFunction<float>,
                                           const float*, const float*, const float*, float*);

}  // namespace dyngen_report
