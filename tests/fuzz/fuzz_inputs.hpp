#pragma once
// What the fuzz targets feed the package (make fuzz: libFuzzer, ASan + UBSan), and what the unit
// tests replay from the inputs that once broke it (tests/fuzz/regressions/<kind>/). Each input must
// be read or refused with a message: never a crash, a sanitizer report, another exception or a hang.
//   scene_text  any bytes as a scene file (parse_scene): a Scene or a SceneError;
//   set_values  the lines of the input as --set overrides (table.key=value) of a valid scene: a
//               Scene or a SceneError;
//   checkpoint  any bytes as a checkpoint's payload after this code's id, in a whole file (magic,
//               format and checksum right, so that the reader's own checks are what is fuzzed): its
//               scene read back (checkpoint_scene) and its state loaded into a small run
//               (load_checkpoint), each done or a CheckpointError.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "io/checkpoint.hpp"
#include "io/provenance.hpp"
#include "scene/run_scene.hpp"
#include "scene/scene.hpp"

namespace rbc::fuzz {

// An error must say something.
inline void check_message(const std::exception& e) {
  if (std::string(e.what()).empty()) __builtin_trap();
}

// A valid scene small enough to build in a fraction of a second: the narrow channel on a coarse
// mesh with one cell.
inline const char* kSmallScene = R"(
[channel]
length = 20e-6
height = 10e-6
mesh_size = 1e-6
reynolds = 0.5556
[time]
dt = 4e-8
end = 4e-7
[[cell]]
center = [5e-6, 3e-6]
swelling_ratio = 0.55
)";

inline void scene_text(const std::uint8_t* data, std::size_t size) {
  try {
    (void)parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const SceneError& e) {
    check_message(e);
  }
}

inline void set_values(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> overrides;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  for (std::string line; std::getline(in, line) && overrides.size() < 16;) overrides.push_back(line);
  try {
    (void)parse_scene(kSmallScene, "fuzz.toml", overrides);
  } catch (const SceneError& e) {
    check_message(e);
  }
}

// The small run the checkpoints are loaded into, built once (its shape preparation takes seconds
// under the sanitizers: prepare() builds it before the first input, outside libFuzzer's timeout).
inline Simulation& small_run() {
  static Simulation sim(parse_scene(kSmallScene, "fuzz.toml"));
  return sim;
}
inline void prepare() { (void)small_run(); }

inline void checkpoint(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("rbcflow_fuzz_checkpoint." + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  Simulation& sim = small_run();
  // This input alone in the folder (no earlier input's file kept as .prev to fall back to).
  std::filesystem::remove(dir / "checkpoint.bin");
  std::filesystem::remove(dir / "checkpoint.bin.prev");
  CheckpointWriter w;
  w.put(std::string(code_id()));
  w.put_raw(data, size);
  w.commit((dir / "checkpoint.bin").string());
  try {
    (void)checkpoint_scene(dir.string());
  } catch (const CheckpointError& e) {
    check_message(e);
  }
  try {
    load_checkpoint(dir.string(), sim);
  } catch (const CheckpointError& e) {
    check_message(e);
  }
}

}  // namespace rbc::fuzz
