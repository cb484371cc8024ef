#pragma once
// A scene in motion: the parts of the method the scene needs, advanced by the study's Lie scheme
// (or, to second order, its extrapolation, [time] scheme = "lie-extrapolated", or the BDF2 form of
// its steps, "bdf2").
// A cell-free channel composes the fluid alone (no membrane code); cells add the membrane step.
#include <memory>
#include <string>
#include <vector>

#include "diagnostics/cell_diagnostics.hpp"
#include "fictitious_domain/dlm_obstacle_step.hpp"
#include "fictitious_domain/rigid_disks.hpp"
#include "fluid/channel_flow.hpp"
#include "immersed_boundary/explicit_coupling.hpp"
#include "immersed_boundary/membrane_coupling.hpp"
#include "semi_implicit/semi_implicit_coupling.hpp"
#include "scene/scene.hpp"

namespace rbc {

// A run that cannot go on (instability): the message names the cause, the time and the cell.
struct RunFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Largest spring strain |l − l0|/l0 a healthy run may show; beyond it the explicit coupling has
// gone unstable (the study's cells stay within a few per cent).
inline constexpr double kMaxMembraneStrain = 1.0;
// Largest fluid speed a healthy run with cells may show, in units of the driving flow's own
// scale (the cell-free peak speed, or the wall speed). An unstable membrane coupling can saturate
// below the CFL and strain limits: measured: the explicit coupling just above its
// limit ran for 0.1 ms with the fluid at 5.9-18 times the flow's peak speed and 5-25 % strain
// (one cell, wide channel, 9e-8 s; 100 cells, 7.5e-8 s; one cell, narrow channel, 6.5e-8 s: an
// episode of 40 us); calm runs of both couplings — 1 to 100 cells, Re0 = 0.01 to 50, Hct 34 %,
// 6e-6 s semi-implicit — stayed at 0.78-1.00 times it.
inline constexpr double kMaxSpeedRatio = 3.0;
// A physical start can be that fast for a moment: a stiff cell released from rest (the CGS reading,
// s* = 1, narrow channel, h = 0.125 um) pushes the fluid to 3.6-4.4 times the flow's peak, above 3
// times for 0.76-1.2 ρh²/μ (Δt = 3e-10 to 1.2e-9 s: one smooth pulse that does not depend on Δt;
// ρh²/μ is the fluid's viscous time across a mesh cell), while the oscillations above stayed
// beyond 3 times for 530 (narrow), 1191 (wide, one cell) and 747 ρh²/μ (100 cells). So a run
// stops once its fluid has spent, in all, kSpeedExcessViscousTimes × ρh²/μ above kMaxSpeedRatio,
// or at once beyond kBurstSpeedRatio: an explicit membrane blowing up can calm down again within
// that time (narrow channel, h = 0.5 um, k_l × 10 and × 100 from rest at Δt = 3.97e-8 and
// 1.14e-8 s: 111 and 336 times the peak for 7.4 and 9.2 ρh²/μ), far beyond any start-up pulse.
inline constexpr double kSpeedExcessViscousTimes = 20.0;
inline constexpr double kBurstSpeedRatio = 10.0;

class Simulation {
 public:
  // options: how the semi-implicit coupling solves its system (its defaults are the measured
  // winners; tests and the benchmark set others). They change the cost, not the step.
  explicit Simulation(const Scene& scene, const CouplingOptions& options = {});

  // One step tⁿ → tⁿ⁺¹ of the scene's time integration ([time] scheme): the study's Lie scheme
  // L_Δt, or ("lie-extrapolated", paper/method/07_second_order_in_time.md) its local Richardson
  // extrapolation Xⁿ⁺¹ = 2 L_{Δt/2}(L_{Δt/2}(Xⁿ)) − L_Δt(Xⁿ), X = (u, p, membrane nodes, disks).
  // The counters (contact and repulsion steps, coupling iterations, the coupling's cost) are the
  // L_Δt step's; the half steps keep their own. Or ("bdf2", paper/method/08_bdf2.md) the same
  // steps in BDF2's form, started by one extrapolated Lie step.
  void step();
  // The fluid as the developed cell-free profile instead of rest (the study starts from rest;
  // benchmarks use this to time steps in a flow that moves the cells as a long run does).
  void start_from_cell_free_profile() { flow_.set_poiseuille(); }
  // Cell k starts from the caller's own nodes instead of its prepared shape (same target area;
  // the area drift is then measured from these nodes), before the first step. A start away from
  // rest: e.g. the polygon inscribed in the circle of radius R0, whose springs are 0.0285 % short
  // of l0 (tests of the health check's start-up rule). Throws std::invalid_argument if k or the
  // node count is wrong or the run has begun.
  void place_cell(std::size_t k, const Points& nodes);
  // Stops the run (RunFailure) on non-finite values, a CFL number above the stability limit,
  // a membrane strain above kMaxMembraneStrain, a membrane node outside the channel or inside an
  // obstacle or a disk, two membranes crossing each other (membrane_crossing.hpp), or a fluid
  // that has been faster than kMaxSpeedRatio times the flow's peak for too long (call it after
  // every step: it adds up that time).
  void check_health();

  const ChannelFlow& flow() const { return flow_; }
  // The fluid's state (u, p) for analyses that set it between steps (tests: the linearised step).
  ChannelFlow& flow() { return flow_; }
  const Scene& scene() const { return scene_; }
  const std::vector<Cell>& cells() const { return cells_; }
  // The pressure (Pa, on the pressure nodes): the flow's, and in the BDF2 scheme plus the
  // membranes' share p_B that its step 4 leaves out of the flow's (simulation.cpp), as the last
  // step found it (not in checkpoints: a resumed run has it after its first step).
  std::vector<double> pressure_with_membranes() const;
  const MembraneModel& membrane() const { return model_; }
  double time() const { return flow_.time(); }
  long steps() const { return flow_.steps(); }
  int last_cg_iterations() const { return last_projection_.iterations; }
  // The fictitious domain of the scene's obstacles (null: no obstacle, none of it built).
  const ObstacleConstraint* obstacles() const { return obstacles_.get(); }
  // The scene's rigid disks (position, velocity, spin) and their step-4 constraint (null: none).
  const std::vector<Disk>& disks() const { return disks_; }
  const DiskConstraint* disk_constraint() const { return disk_constraint_.get(); }
  // The disks' contact forces (N/m) where they are now: for a gap g below the range ρ to another
  // disk or a wall, strength · ((ρ − g)/ρ)² along the line of centres or the wall's normal (the
  // repulsion of Glowinski, Pan, Hesla & Joseph 1999 with the gap written out). Central: no torque.
  std::vector<Eigen::Vector2d> contact_forces() const;
  long contact_steps() const { return contact_steps_; }  // steps in which a contact force acted
  long repulsion_steps() const { return repulsion_steps_; }  // steps in which the membrane repulsion acted
  // GMRES iterations of the semi-implicit coupling's cell-to-cell system (0: explicit or one cell).
  int last_coupling_iterations() const { return coupling_ ? coupling_->last_iterations() : 0; }
  // Checkpoints: the state the next step needs (fluid, membranes, coupling), not the scene.
  void save(CheckpointWriter& w) const;
  void load(CheckpointReader& r);  // into a Simulation built from the same scene
  // The semi-implicit step (its cost breakdown), or null.
  const SemiImplicitMembraneStep* semi_implicit_step() const { return dynamic_cast<const SemiImplicitMembraneStep*>(coupling_.get()); }
  SemiImplicitMembraneStep* semi_implicit_step() { return dynamic_cast<SemiImplicitMembraneStep*>(coupling_.get()); }

 private:
  Scene scene_;
  ChannelFlow flow_;
  MembraneModel model_;
  CouplingOptions options_;
  std::vector<Cell> cells_;
  // Only when the scene has cells: the coupling the scene chose ([time] coupling).
  std::unique_ptr<MembraneCoupling> coupling_;
  // Only when the scene has obstacles: step 4's multiplier (installed in the fluid's diffusion).
  std::unique_ptr<ObstacleConstraint> obstacles_;
  // Only when the scene has disks: their state and step 4's rigid-motion multiplier.
  std::vector<Disk> disks_;
  std::unique_ptr<DiskConstraint> disk_constraint_;
  VelocityField contact_field_;  // step 4's force density with the contact forces (and f_B)
  long contact_steps_ = 0;
  long repulsion_steps_ = 0;
  // [time] scheme = "lie-extrapolated": the same scene at Δt/2 (its scheme "lie"), which takes
  // this run's state before each step and runs two steps (null: the study's scheme).
  std::unique_ptr<Simulation> half_step_;
  // [time] scheme = "bdf2" (paper/method/08_bdf2.md): the nodes' history, per cell, s^{n−1}
  // (the last positions step 2 found) and s̃^{n−1} = (4 s^{n−1} − s^{n−2})/3; the cells' nodes
  // themselves hold the extrapolated 2 s^{n−1} − s^{n−2}, the positions at tⁿ.
  std::vector<Points> bdf_last_, bdf_tilde_, bdf_extra_force_;
  VelocityField bdf_force_;                 // P f_B, step 4's force density
  std::vector<double> bdf_force_pressure_;  // p_B, its gradient part's pressure (Pa)
  bool bdf_move_known_ = false;  // after the Lie start: s¹ is the start's, no move in the next step 2
  void start_bdf2();              // the first step: the extrapolated Lie step, which leaves BDF2 its history
  void bdf2_step();               // the next ones
  const VelocityField* bdf2_membrane_step();
  void take_state(const Simulation& from);       // u, p, clock, membrane nodes, disks
  void extrapolate_with(const Simulation& finer);  // that state ← 2 (finer's) − (this one's)
  // One step of the study's Lie scheme; its parts, in its order.
  void lie_step();
  void hold_disks_where_they_will_be();
  const VelocityField* membrane_step();  // step 4's force density: f_B and the disks' contact forces (null: none)
  void coupling_after_step4();  // what the cells' coupling adds to u^{n+1} (the semi-implicit one's correction)
  void count_repulsion();       // after step 2: one more step in which the membrane repulsion acted, if it did
  void move_disks();
  ProjectionReport last_projection_;
  double speed_excess_time_ = 0;  // s the fluid has spent above kMaxSpeedRatio × the flow's peak (check_health)
  void check_disks(const std::string& when) const;  // check_health's part for the disks
  // Step 4's force density with the contact forces added (f_B itself when none acts).
  const VelocityField* add_contact_forces(const VelocityField* f_B);
  void build_cells();
};

}  // namespace rbc
