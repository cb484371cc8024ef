// libFuzzer target for the scene parser: any byte string must either parse or end in a
// SceneError with a message — never a crash, a sanitizer report, another exception or a hang.
//   make fuzz                       (clang; FUZZ_SECONDS=120 by default)
// Inputs it finds that break this go to tests/fuzz/regressions/ and into the corpus test
// (tests/test_malformed_inputs.cpp, FuzzRegressions).
#include <cstddef>
#include <cstdint>
#include <string>

#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)rbc::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const rbc::SceneError& e) {
    if (std::string(e.what()).empty()) __builtin_trap();  // an error must say something
  }
  return 0;
}
