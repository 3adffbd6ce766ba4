// The checks' comparison (dyngen/check_impl.hpp) for double and float, compiled once for the
// hundred generated packages whose checks the tests build, which see only its declarations
// (DYNGEN_CHECK_EXTERN).
#include <dyngen/check_impl.hpp>

namespace dyngen::check {

#define DYNGEN_CHECK_INSTANTIATE(S)                                                        \
  template void bit_for_bit<S>(const Model<S>&, States, const char*, Function<S>);         \
  template void batch_bit_for_bit<S>(const Model<S>&, States, int, const char*, Function<S>, \
                                     ManyFunction<S>);                                      \
  template void model_matches<S>(const Model<S>&, int, int, const char* const*);
DYNGEN_CHECK_INSTANTIATE(double)
DYNGEN_CHECK_INSTANTIATE(float)
#undef DYNGEN_CHECK_INSTANTIATE

}  // namespace dyngen::check
