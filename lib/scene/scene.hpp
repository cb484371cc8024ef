#pragma once
// A scene: everything one run needs, read from a TOML file in SI units (SPEC section 8).
//
//   [fluid]   density (kg/m³), viscosity (Pa·s)                       — optional, plasma by default
//   [channel] length, height, mesh_size (m); reynolds (cell-free Re0) or body_force (N/m³);
//             wall_velocity = [bottom, top] (m/s)
//   [time]    dt, end (s); coupling ("explicit"); advection_substeps (Q)
//   [solver]  pressure_preconditioner ("schur" | "laplacian"), cg_tolerance
//   [output]  every (s between samples), vtk (bool)
//
// Cells, disks and obstacles ([membrane], [[cell]], [[disk]], [[obstacle]]) are named in SPEC
// section 8; this version reads cell-free channels and refuses those tables with a clear message.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "fluid/channel_flow.hpp"

namespace rbc {

// Bad input: the message names the file, the key and what is allowed.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Scene {
  std::string source;  // where it was read from, for messages
  FluidProperties fluid;
  double length = 0, height = 0, mesh_size = 0;  // m
  std::optional<double> reynolds0;                // cell-free Reynolds number, or
  std::optional<double> body_force;               // f_p, N/m³
  double wall_velocity[2] = {0.0, 0.0};           // m/s, bottom and top
  double dt = 0, end = 0;                         // s
  std::string coupling = "explicit";
  int advection_substeps = 1;
  std::string pressure_preconditioner = "schur";
  double cg_tolerance = 1e-10;
  double output_every = 0;  // s; 0 means end/100
  bool vtk = false;

  double driving_force() const;  // f_p, N/m³, from whichever was given
  ChannelFlowParams flow_params() const;
  double sample_interval() const { return output_every > 0 ? output_every : end / 100; }
};

// Reads and validates a scene. overrides are "table.key=value" strings (value in TOML syntax;
// a bare word is taken as a string) applied before validation. Throws SceneError.
Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& source, const std::vector<std::string>& overrides = {});

}  // namespace rbc
