#pragma once
// A scene: everything one run needs, read from a TOML file in SI units (every key: paper/scene_keys.md).
//
//   [fluid]   density (kg/m³), viscosity (Pa·s)                       — optional, plasma by default
//   [channel] length, height, mesh_size (m); reynolds (cell-free Re0) or body_force (N/m³);
//             wall_velocity = [bottom, top] (m/s)
//   [time]    dt, end (s); coupling ("explicit" | "semi-implicit"); advection_substeps (Q);
//             projection ("study" | "incremental": the pressure's form, ChannelFlowParams;
//             "incremental" by default with obstacles, "study" otherwise)
//   [solver]  pressure_preconditioner ("schur" | "laplacian"), cg_tolerance, cg_max_iterations, coupling_tolerance
//             (relative residual of the semi-implicit coupling's cell-to-cell system)
//   [output]  every (s between samples), vtk (bool: ParaView files, lib/scene/vtk_output.hpp),
//             vtk_every (s between them; at least every, default end/100), snapshots = [t, …] (s; membrane shapes),
//             fields (bool: the velocity field at the snapshot times, field_<k>.dat), frames (movie
//             frames over the run: frames.dat, lib/scene/movie_frames.hpp; 0 = none, the default)
//   [membrane] nodes, radius (m), kl, kb, ks (the study's numbers), units ("si" | "cgs"),
//              area_penalty (E_s in the flow force, bool)            — optional, the study's values
//   [[cell]]  center = [x, y] (m), swelling_ratio (s*), angle (rad, long axis from x1),
//             kb_scale (this cell's k_b over [membrane] kb; the study's stiffer cells, Sec. 3.1.2)
//   [[obstacle]] x = [a, b], y = [c, d] (m), a fixed rectangle held by the fictitious-domain
//             method (lib/fictitious_domain); its edges on mesh lines; wall = "bottom" | "top"
//             (optional: checked that it stands on that wall). [solver] obstacle_tolerance
//             (velocity left on the obstacle, relative to the field's largest), obstacle_preconditioner
//             ("capacitance" | "none": the Uzawa CG's).
//
//   [contact] range (m, default 2h), strength (N/m): the disks' short-range repulsion (GPHJ 1999),
//             F = strength ((range − gap)/range)² along the line of centres (another disk) or the
//             wall's normal, for a gap below range (simulation.hpp)
//   [repulsion] range (m, default h), strength (N/m, default 0 = off): a short-range repulsion of
//             membrane nodes from the walls and from other cells' nodes, s (1 − d/ρ)² within ρ
//             (lib/membrane/membrane_repulsion.hpp; not in the study: keeps crowded cells from crossing);
//             range at most 3h
//   [[disk]]  center = [x, y] (m), radius (m): a neutrally buoyant rigid disk moving freely with
//             the flow, held rigid by the fictitious-domain method (lib/fictitious_domain/
//             rigid_disks.hpp). [solver] disk_tolerance (the velocity defect left on the disks,
//             relative to the field's largest), disk_boundary_spacing (the collocation points on
//             each disk's boundary about that many h apart; 1: the method's choice). Disks and
//             obstacles in one scene are not supported yet. Use the study's pressure form with disks ([time] projection =
//             "study", the default): the incremental form's lagged pressure pushes a spinning,
//             moving disk sideways at ≈ ω V Δt (tests/test_rigid_disks.cpp).
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "fictitious_domain/obstacles.hpp"
#include "fluid/channel_flow.hpp"
#include "membrane/spring_membrane.hpp"

namespace rbc {

// Largest mobility table the semi-implicit coupling may allocate (step_mobility.hpp), GiB.
inline constexpr double kMaxMobilityTableGiB = 8.0;
// Largest mesh (velocity nodes; ≈ 1 KB of fields and solver factors per node) and membrane
// (nodes per cell; preparing a shape costs ≈ N³) a scene may ask for.
inline constexpr double kMaxVelocityNodes = 4e6;
inline constexpr int kMaxMembraneNodes = 400;
// Most movie frames a run may write (frames.dat: about 2 kB a cell and frame).
inline constexpr int kMaxMovieFrames = 2000;
// The most steps a scene may ask for (end / dt): far beyond any run, and within a 64-bit count.
inline constexpr double kMaxSteps = 1e12;

// Bad input: the message names the file, the key and what is allowed.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CellSpec {
  Eigen::Vector2d center{0, 0};  // m
  double swelling_ratio = 1.0;   // s*
  double angle = 0.0;            // rad
  double kb_scale = 1.0;         // this cell's k_b over [membrane] kb (k_l, k_s unchanged)
};

struct DiskSpec {
  Eigen::Vector2d center{0, 0};  // m
  double radius = 0;             // m
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
  // "study": the study's Lie scheme (the whole pressure in step 1); "incremental": step 4 carries
  // the last pressure and step 1 finds its increment (ChannelFlowParams::incremental_pressure).
  // A scene file without the key gets "incremental" when it has obstacles.
  std::string projection = "study";
  // The time integration: "lie", the study's Lie scheme, one step a step (first order);
  // "lie-extrapolated", each step that Lie step and two of half its Δt, extrapolated
  // 2 L_{Δt/2} L_{Δt/2} − L_Δt (second order with projection "incremental", about 1.4 with the
  // study's form; not in the study: paper/method/07_second_order_in_time.md); "bdf2", the same
  // steps in BDF2's form, one extrapolated Lie step to start (second order, with projection "incremental";
  // channels without obstacles or disks; not in the study: paper/method/08_bdf2.md).
  std::string scheme = "lie";
  // In "lie-extrapolated": whether the pressure is extrapolated with the rest of the state (true)
  // or taken from the two half steps (false: an evidence run of chapter 7, where extrapolating it
  // is what grows unstable next to fixed obstacles; first order in the velocity there). It
  // changes a run only in the incremental form, whose step 4 reads the last pressure.
  bool extrapolate_pressure = true;
  std::string pressure_preconditioner = "schur";
  double cg_tolerance = 1e-10;
  int cg_max_iterations = 200;  // the Laplacian preconditioner's CG: a run whose CG stops short of cg_tolerance stops
  // Semi-implicit coupling, several cells: relative residual of the GMRES solve. It only sets how
  // well the linearised force is predicted (the scheme is first order whatever it is); measured
  // at 100 cells (Δt = 2e-6 s, 0.2 ms): 1e-3 and 1e-5 give Re within 3e-5 of each other, with 6
  // and 10 iterations per step.
  double coupling_tolerance = 1e-4;
  double output_every = 0;  // s; 0 means end/100 (at least dt)
  bool vtk = false;
  double vtk_every = 0;     // s; 0 means vtk_interval()
  std::vector<double> snapshots;  // s, sorted
  bool field_snapshots = false;   // [output] fields: the velocity field at the snapshot times too
  int frames = 0;                 // [output] frames: movie frames over the run, frame k at k end/frames (0: none)
  // Cells (empty: a cell-free channel).
  MembraneConstants membrane_constants;
  int membrane_nodes = 76;          // N
  double membrane_radius = 2.8e-6;  // R0, m
  bool area_penalty = true;         // E_s in the force during the flow
  std::vector<CellSpec> cells;
  // Fixed obstacles (empty: no fictitious domain is built).
  std::vector<Obstacle> obstacles;
  double obstacle_tolerance = 1e-10;
  std::string obstacle_preconditioner = "capacitance";
  // Freely moving rigid disks (empty: none of it is built).
  std::vector<DiskSpec> disks;
  double disk_tolerance = 1e-10;
  double disk_boundary_spacing = 1.0;  // h
  // The disks' contact force (Simulation::contact_forces). Strength: 1e-3 N/m, about 100 times the
  // drag on a disk of radius 2.8 um moving across the flow at 1 mm/s (≈ 10 μ v per unit length),
  // the lateral speeds of the study's migrations; range: 2h, so that it acts before the run's
  // stop at a gap of one mesh cell.
  double contact_range = 0;         // m (set to 2h when read)
  double contact_strength = 1e-3;   // N/m
  // The membranes' repulsion (membrane_repulsion.hpp): off unless strength > 0.
  double repulsion_range = 0;       // m (set to h when read)
  double repulsion_strength = 0;    // N/m
  double fluid_area() const;  // m², L H minus the obstacles
  MembraneModel membrane_model() const {
    return MembraneModel::from(membrane_constants, membrane_nodes, membrane_radius, area_penalty);
  }

  double driving_force() const;  // f_p, N/m³, from whichever was given
  ChannelFlowParams flow_params() const;
  // The smallest Q (wave-like substeps) whose advective bound Q * 0.5 h / U_max covers dt on this
  // scene's channel (the bound depends on h and the flow, not on dt or Q).
  int advection_substeps_for(double dt) const;
  // s between samples; by default 100 samples, at most one per step.
  double sample_interval() const { return output_every > 0 ? output_every : std::max(end / 100, dt); }
  // s between ParaView files ([output] vtk): by default 100 over the run, at most one per sample.
  double vtk_interval() const { return vtk_every > 0 ? vtk_every : std::max(end / 100, sample_interval()); }
};

// Reads and validates a scene. overrides are "table.key=value" strings (value in TOML syntax;
// a bare word is taken as a string) applied before validation. Throws SceneError.
Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& source, const std::vector<std::string>& overrides = {});
// Every key a scene may hold, as "table.key" ("cell.center" for [[cell]] center, …): the parser's
// own list, which paper/scene_keys.md documents (a test keeps the two the same).
std::vector<std::string> scene_keys();
// The scene as a TOML file that parse_scene reads back to the same values (every number with 17
// significant digits): what a checkpoint stores and compares.
std::string scene_to_toml(const Scene& scene);

}  // namespace rbc
