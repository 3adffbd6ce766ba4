// The MPFR reference of dyngen report's harness: the runtime's algorithms on mpreal numbers.
#include <dyngen/dyngen.hpp>
#include <dyngen/numerics/reference.hpp>

#include "dyngen/report/harness.hpp"

namespace dyngen_report {

struct Reference::Impl {
  dyngen::numerics::ExactDynamics dynamics;
  std::vector<std::vector<dyngen::numerics::Exact>> outputs;
};

Reference::Reference(const dyngen::Model<double>& model, int bits)
    : impl_(new Impl{dyngen::numerics::ExactDynamics(
                           model, std::max(dyngen::numerics::exact_bits, bits)),
                       {}}) {}

Reference::~Reference() = default;

int Reference::bits() const { return impl_->dynamics.bits(); }

double Reference::error_floor() { return dyngen::numerics::error_floor; }

void Reference::set_consistent_torques(dyngen::numerics::State& s) {
  dyngen::numerics::set_consistent_torques(impl_->dynamics, s);
}

void Reference::compute(std::string_view algorithm,
                        const std::vector<std::span<const double>>& x) {
  impl_->outputs = impl_->dynamics.run(algorithm, x);
}

double Reference::error(const std::vector<std::vector<double>>& y) const {
  double error = 0;
  for (std::size_t j = 0; j < y.size(); ++j)
    error = std::max(error, dyngen::numerics::relative_error(y[j], impl_->outputs[j]));
  return error;
}

}  // namespace dyngen_report
