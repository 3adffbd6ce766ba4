// Fuzz target: any bytes as a chain spec (YAML; the first byte chooses the load options).
#include <cstddef>
#include <cstdint>

#include "fuzz_robot.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  dyngen::fuzz::load_and_generate(
      "fuzz.yaml", std::string(reinterpret_cast<const char*>(data) + 1, size - 1), data[0]);
  return 0;
}
