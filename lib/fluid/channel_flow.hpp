#pragma once
// The plasma in the periodic channel: state (u, p, t) and the three fluid steps of the study's
// Lie scheme (its Section 2.4). The membrane step (2) belongs to the cells: whoever owns cells
// hands it to step(), which calls it between project() and advect(); a cell-free channel just
// leaves it out.
#include <functional>
#include <string>

#include "fluid/diffusion.hpp"
#include "fluid/quasi_stokes.hpp"
#include "io/checkpoint.hpp"
#include "fluid/wave_like_advection.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

struct FluidProperties {
  double density = 1000.0;    // ρ, kg/m³ (plasma: reference-data/README.md)
  double viscosity = 1.2e-3;  // μ, Pa·s
};

// The driving force of a cell-free Poiseuille flow with mean velocity U0 = Re0 μ / (ρ H):
// f_p = 12 μ U0 / H² (N/m³).
double body_force_from_reynolds(double reynolds0, const FluidProperties& fluid, double height);

struct ChannelFlowParams {
  FluidProperties fluid;
  double length = 20e-6;      // L, m (period in x1)
  double height = 10e-6;      // H, m
  double mesh_size = 0.125e-6;  // h, m
  double body_force = 0.0;    // f_p along x1, N/m³
  double wall_velocity[2] = {0.0, 0.0};  // x1-velocity of the bottom and top walls, m/s
  double dt = 1e-7;           // Δt, s
  int advection_substeps = 1;  // Q, wave-like substeps per step
  PressurePreconditioner preconditioner = PressurePreconditioner::schur;
  double cg_tolerance = 1e-10;  // relative residual of the pressure CG
  // false: the study's Lie scheme — step 1 finds the whole pressure p^{n+1}, step 4 has none.
  // true: the incremental form (van Kan, SIAM J. Sci. Stat. Comput. 7 (1986) 870) — step 4 carries
  // the pressure force of p^n, step 1 projects and finds only the increment φ, p^{n+1} = p^n + φ.
  // Same velocity operator in step 1; in a steady flow φ = 0, so the state is divergence-free
  // exactly, also where step 4 imposes an obstacle's u = 0 (the study's form leaks through a
  // fixed obstacle by ≈ 12 μΔt/(ρ H²) of the flux: paper/method/05_fictitious_domain.md).
  bool incremental_pressure = false;
  // true: the BDF2 scheme's fluid steps (paper/method/08_bdf2.md; with incremental_pressure):
  // step 3 transports the last two projected velocities, step 4 is BDF2's,
  //
  //   ρ (3u^{n+1} − 4ûⁿ + û^{n−1})/(2Δt) − μΔu^{n+1} = f − ∇pⁿ,
  //
  // i.e. step 4's implicit diffusion at Δt' = 2Δt/3 from w = (4ûⁿ − û^{n−1})/3, and step 1
  // projects with the same Δt'. Its first step needs the history another scheme's first step
  // leaves (start_bdf2; Simulation takes the extrapolated Lie step).
  bool bdf2 = false;
  int cg_max_iterations = 200;
};

// Largest cell-free speed the flow can reach (Poiseuille peak f H²/(8μ) plus the wall speed),
// m/s, and the advective bound on Δt that follows (Q kAdvectiveCfl h / U_max), s.
double cell_free_peak_speed(const ChannelFlowParams& p);
double advective_dt_bound(const ChannelFlowParams& p);

class ChannelFlow {
 public:
  explicit ChannelFlow(const ChannelFlowParams& params);

  // Step 1: quasi-Stokes projection (u^{n+1/3}).
  ProjectionReport project();
  // Step 3: wave-like advection of u by itself (u^{n+2/3}); in the BDF2 scheme, of the last two
  // projected velocities to t^{n+1} and their combination w (params().bdf2).
  void advect();
  // Step 4: implicit diffusion with the body force and an optional force field (u^{n+1});
  // advances the clock.
  void diffuse(const VelocityField* force_field = nullptr);
  // After step 4: adds a velocity change (m/s) — step 4's response to the linearly implicit
  // membrane force of the semi-implicit coupling. Does not advance the clock.
  void add_velocity(const VelocityField& du) {
    for (std::size_t k = 0; k < u_.u1.size(); ++k) {
      u_.u1[k] += du.u1[k];
      u_.u2[k] += du.u2[k];
    }
  }
  ImplicitDiffusion& diffusion() { return diffusion_; }
  // One step of the Lie scheme, tⁿ → tⁿ⁺¹: steps 1, 2, 3, 4. Step 2 is the caller's membrane
  // step: it moves the cells with u^{n+1/3} and returns the force density step 4 adds to f_p
  // (N/m³; null: none). Without one (a cell-free channel) step 2 has nothing to move.
  using MembraneStep = std::function<const VelocityField*()>;
  ProjectionReport step(const MembraneStep& membrane_step = nullptr);

  void set_poiseuille();  // u = the exact cell-free steady profile (for tests and warm starts)

  const ChannelMesh& mesh() const { return mesh_; }
  const ChannelFlowParams& params() const { return p_; }
  // The Δt of the implicit parts (step 4's diffusion, step 1's pressure scale, the semi-implicit
  // coupling): Δt in the Lie scheme, 2Δt/3 in the BDF2 scheme (s).
  double implicit_dt() const { return p_.bdf2 ? 2.0 * p_.dt / 3.0 : p_.dt; }
  VelocityField& velocity() { return u_; }
  const VelocityField& velocity() const { return u_; }
  const std::vector<double>& pressure() const { return pressure_; }
  std::vector<double>& pressure() { return pressure_; }
  const QuasiStokesProjection& projection() const { return projection_; }
  QuasiStokesProjection& projection() { return projection_; }
  double time() const { return t_; }
  long steps() const { return steps_; }
  // The extrapolated scheme (Simulation, [time] scheme = "lie-extrapolated"): u, p and the clock
  // from another flow on the same mesh.
  void take_state(const ChannelFlow& from);
  // The BDF2 scheme's start: the state after the first step, taken by a flow in the Lie form on
  // the same mesh at the same Δt that kept its stages (keep_stages): u, p, the clock and step
  // count, and as history its projected velocity P u⁰ and that velocity advected to t¹, û⁰ (with
  // an error O(Δt²), once). The first step's own accuracy is the caller's (Simulation::start_bdf2).
  void start_bdf2(const ChannelFlow& lie);
  // Keep the last step's projected and advected velocities (for start_bdf2).
  void keep_stages() { keep_stages_ = true; }
  // Whether the BDF2 scheme has its history (a start_bdf2 or a checkpoint of a BDF2 run).
  bool has_bdf2_history() const { return history_; }
  // Checkpoints: velocity, pressure (the warm start of the next projection), clock.
  void save(CheckpointWriter& w) const;
  void load(CheckpointReader& r);

 private:
  void apply_wall_velocity();
  ChannelFlowParams p_;
  ChannelMesh mesh_;
  QuasiStokesProjection projection_;
  WaveLikeAdvection advection_;
  ImplicitDiffusion diffusion_;
  VelocityField u_;
  std::vector<double> pressure_;
  std::vector<double> increment_;  // φ of the incremental form
  VelocityField step4_force_;      // the incremental form's pressure force (+ the caller's field)
  double t_ = 0.0;
  long steps_ = 0;
  // The BDF2 scheme's history: P u^{n−1} and û^{n−1}, that velocity advected over its step
  // (kept_projected_, kept_advected_ hold this step's, which become them).
  bool keep_stages_ = false, history_ = false;
  VelocityField kept_projected_, kept_advected_, previous_projected_, previous_advected_, advecting_;
};

}  // namespace rbc
