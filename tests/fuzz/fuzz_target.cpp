// libFuzzer target for one kind of input of tests/fuzz/fuzz_inputs.hpp, chosen at build time
// (RBCFLOW_FUZZ_KIND: scene_text, set_values or checkpoint; make fuzz builds and runs each).
#include <cstddef>
#include <cstdint>

#include "fuzz_inputs.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  rbc::fuzz::prepare();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rbc::fuzz::RBCFLOW_FUZZ_KIND(data, size);
  return 0;
}
