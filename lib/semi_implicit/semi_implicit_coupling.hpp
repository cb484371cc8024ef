#pragma once
// The semi-implicit coupling ("semi-implicit" in scenes; not in the study): the study's scheme with the
// spring force of step 4 taken linearly implicit, in the spirit of Newren, Fogelson, Guy & Kirby,
// JCP 222 (2007). Same energies, same forces, same steps 1-3.
//
// Step 2 is the study's: r^{n+1} = r^n + Δt U(r^n) with u^{n+1/3}, F^{n+1} = F(r^{n+1}).
// In step 4 the force is the one at the position the nodes will reach with u^{n+1},
//
//   F ≈ F(r^{n+1} + Δt J u^{n+1}) ≈ F^{n+1} − Δt K J u^{n+1}      (K: membrane_stiffness)
//
// so the diffusion solve A u^{n+1} = b + S F^{n+1} − Δt S K J u^{n+1} is implicit in the stiff part
// of the membrane. The velocity that will move the nodes is the projected one (step 1 of the next
// step), so J u^{n+1} above means J P u^{n+1}. Step 4 is linear in the force, so with
// u⁰ = A⁻¹(b + S F^{n+1}) (the explicit step 4) and M = J P A⁻¹ P S (StepMobility), the node
// velocities U = J P u^{n+1} solve the small system
//
//   (I + Δt M K) U = J P u⁰                                 (2N unknowns per cell)
//
// and u^{n+1} = u⁰ + A⁻¹ S (−Δt K U): one more fast solve per step, a product's (with several
// cells not even that: U is a combination of GMRES's product arguments, whose responses A⁻¹ S K z
// it keeps).
// (Δt here and in A is the flow's implicit_dt(): Δt, or 2Δt/3 in the BDF2 scheme, whose step 2
// and explicit force differ: paper/method/08_bdf2.md.)
// With M and K positive semi-definite
// every membrane mode is damped like backward Euler, whatever Δt: the stable Δt is set by the
// flow (the advective bound), not by k_l and k_b. With several cells the system couples them
// through the fluid; leaving that coupling explicit (each cell with its own block only) was
// unstable at Δt = 2e-6 s for two cells 5 µm apart (measured), so we solve the coupled system by
// GMRES, preconditioned by each cell's own system with M averaged over the cell's phase on the
// grid (StepMobility::phase_averaged_matrix), started from the last steps' solutions carried on
// (solve_coupled); each iteration is one more fast solve and projection (the exact M K v, the
// long way). Since the blocks only precondition, they are rebuilt every few tens of steps when
// there are several cells (the interval shortens by itself when GMRES needs many iterations, as
// at larger Δt), factored in single precision and stored in bfloat16 (GMRES corrects the rest).
//
// Turned blocks (CouplingOptions::turn_blocks). A cell that has turned by a rotation R since its
// block was built has, where the walls and the grid do not matter,
//
//   K(R r) = R K(r) Rᵀ,  M̄(R r) ≈ R M̄(r) Rᵀ   ⇒   B(R r)⁻¹ ≈ R B(r)⁻¹ Rᵀ
//
// (R acting on every node's pair of unknowns; the springs' energies do not change under a
// rotation, and the fluid's response turns with the forces). So the block is applied turned:
// v_i → Rᵀ v_i, B⁻¹, then x_i → R x_i. R is the rotation that best maps the block's nodes r⁰
// onto the cell's nodes r about their centroids (least squares, 2D):
//
//   θ = atan2(Σ_i p_i × q_i, Σ_i p_i · q_i),   p_i = r⁰_i − r̄⁰,  q_i = r_i − r̄,
//
// fitted at every step. A crowd whose cells turn then needs its blocks rebuilt less often
// (paper/method/04_semi_implicit_coupling.md gives the measured ratio).
//
// The products' fluid solves run in single precision where step 4 allows it (coupling_products.hpp).
#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "fluid/channel_flow.hpp"
#include "io/checkpoint.hpp"
#include "semi_implicit/coupling_preconditioner.hpp"
#include "semi_implicit/coupling_products.hpp"
#include "semi_implicit/detail/parallel_spreading.hpp"
#include "immersed_boundary/explicit_coupling.hpp"
#include "immersed_boundary/immersed_boundary.hpp"
#include "immersed_boundary/membrane_coupling.hpp"
#include "semi_implicit/step_mobility.hpp"
#include "membrane/membrane_stiffness.hpp"

namespace rbc {

// How the coupled system is solved: choices that change what a step costs, not the step (each
// takes the same steps to GMRES's tolerance; tests/test_semi_implicit.cpp checks it). The defaults
// are the measured winners (paper/method/04_semi_implicit_coupling.md); tests and the benchmark
// set others. Not scene keys: a scene says what is computed, not how fast.
struct CouplingOptions {
  // Where GMRES starts (solve_coupled): the last step's solution (kConstant), or the last two
  // steps' solutions carried on in a straight line (kLinear); each plus the blocks' response to
  // the change of the right-hand side that the start does not predict.
  enum class Start { kConstant, kLinear };
  Start start = Start::kConstant;
  // Apply each cell's block turned with the cell's rotation since it was built (see above).
  bool turn_blocks = true;
  // The products' fluid solves in single precision where step 4 allows it (coupling_products.hpp).
  CouplingProducts::Precision product_precision = CouplingProducts::Precision::kSingleWherePossible;
  // Where J P of the predictor and the products makes P: over the mesh (kSweep), at the stencils'
  // nodes only (kFootprint, with the exact Schur preconditioner), or at the nodes where they are
  // few against the mesh (kCheaper: a few cells in a wide channel). Same values to round-off.
  enum class Projection { kCheaper, kSweep, kFootprint };
  Projection projection = Projection::kCheaper;
};

// The options in words, e.g. "start constant, blocks turned, products single where possible"
// (summary.json records it; --reuse compares it).
std::string describe(const CouplingOptions& options);

class SemiImplicitMembraneStep final : public MembraneCoupling {
 public:
  using Start = CouplingOptions::Start;
  // tolerance: relative residual of the cell-to-cell GMRES solve (several cells).
  SemiImplicitMembraneStep(ChannelFlow& flow, const MembraneModel& model, double tolerance = 1e-4, const CouplingOptions& options = {});
  // Step 2 (the study's): move the nodes with u^{n+1/3}, spread F^{n+1} for step 4.
  const VelocityField& step(std::vector<Cell>& cells, const VelocityField& u, double dt) override {
    return move_.step(cells, u, dt);
  }
  // Step 2's mover (the scene's membrane repulsion is set on it).
  ExplicitMembraneStep& membrane_move() override { return move_; }
  // After step 4 with F^{n+1}: u = u⁰ in (not changed); returns the velocity change A⁻¹ S (−Δt K U)
  // (m/s, zero on the walls) that turns u⁰ into u^{n+1}: step 4's response to the implicit force.
  const VelocityField* implicit_correction(const std::vector<Cell>& cells, const VelocityField& u) override;
  int last_iterations() const override { return last_iterations_; }
  // Whether the last step made P at the stencils' nodes only (CouplingOptions::projection).
  bool last_projection_at_footprint() const { return project_at_footprint_; }
  // The fluid is no longer invariant under shifts in x1 (an obstacle's multiplier in step 4): the
  // tabulated mobility is then only a preconditioner, and even one cell goes through GMRES, whose
  // products (spread, step 4, project, interpolate) are exact. Call it after the constraint is
  // installed in step 4 (the products' solves are chosen then).
  void set_fluid_not_x1_invariant() override;
  // Checkpoints: the projection's warm start, GMRES's starting point and the nodes the current
  // preconditioner blocks were built at (load rebuilds them from those nodes, so a resumed run
  // takes the same steps bit for bit).
  void save(CheckpointWriter& w) const override;
  void load(CheckpointReader& r, const std::vector<Cell>& cells) override;
  // Where the time goes (wall seconds accumulated since construction; for the benchmark).
  struct Cost {
    double predictor = 0;  // P u⁰ and U⁰ = J P u⁰
    double blocks = 0;     // K of every cell; M_cc and the LU of the blocks when they are rebuilt
    double coupled = 0;    // GMRES: matrix-vector products (spread, solve, project, interpolate) and the rest
    double products = 0, preconditioner = 0;  // of which the products and the preconditioner's sweeps
    double product_spread = 0, product_solve = 0, product_project = 0;  // the products' parts (the rest: interpolation)
    double correction = 0; // spreading −Δt K U
    long steps = 0, block_builds = 0, product_count = 0;
    long fresh_rebuilds = 0;  // steps whose GMRES needed blocks built at their own nodes
  };
  const Cost& cost() const { return cost_; }

  // GMRES: at most kFreshBlocksAfter iterations with the preconditioner's blocks as they are; if
  // that does not converge, the blocks are rebuilt at the nodes of the step and GMRES goes on from
  // its last iterate for at most kCouplingMaxIterations more (then the run stops). The blocks'
  // rebuild rule is the preconditioner's (coupling_preconditioner.hpp).
  static constexpr int kCouplingMaxIterations = 60;
  static constexpr int kFreshBlocksAfter = 20;
  static constexpr int kRebuildAboveIterations = CouplingPreconditioner::kRebuildAboveIterations;
  static constexpr int kBlockRefreshSteps = CouplingPreconditioner::kBlockRefreshSteps;
  // For tests: fresh blocks after this many iterations instead (0: at every step).
  void set_fresh_blocks_after(int iterations) { fresh_blocks_after_ = iterations; }
  // For tests and measurements: the preconditioner's rebuild threshold and longest interval.
  void set_rebuild_above_iterations(int iterations) { preconditioner_.set_rebuild_above_iterations(iterations); }
  void set_block_refresh_steps(int steps) { preconditioner_.set_block_refresh_steps(steps); }

 private:
  ChannelFlow& flow_;
  double tolerance_;
  ChannelMesh mesh_;
  MembraneModel model_;
  double dt_;
  VelocityField projected_;             // P u⁰
  std::vector<double> pressure_;        // its pressure, the warm start of the next predictor (one cell, Laplacian preconditioner)
  std::vector<double> exact_pressure_;  // its pressure in the projection's exact form (no warm start)
  ExplicitMembraneStep move_;
  StepMobility mobility_;
  VelocityField correction_;
  // The coupled system of the current step: each cell's stiffness K_c, and its preconditioner.
  std::vector<MembraneStiffness> stiffness_;
  CouplingPreconditioner preconditioner_;
  std::vector<Eigen::Index> offset_;  // first unknown of each cell
  CouplingOptions options_;
  std::unique_ptr<CouplingProducts> products_;  // the products' fluid solves (and one cell's correction)
  CouplingProducts& products();
  VelocityField work_;                        // GMRES matrix-vector product: the velocity
  Eigen::VectorXd kv_;                        // and K v, the nodes' forces it spreads
  std::vector<VelocityField> responses_;      // A⁻¹ S K z of this step's products, in order
  int products_in_step_ = 0;
  // P at the stencils' nodes only (predict): the footprint, P's values there, and whether this
  // step uses them. A node of it costs about as much as kFootprintNodeCost nodes of the sweep
  // over the mesh (7 measured by bench_channel --disks-only; the footprint's build besides).
  static constexpr std::size_t kFootprintNodeCost = 8;
  StencilFootprint footprint_;
  std::vector<double> footprint1_, footprint2_;
  bool project_at_footprint_ = false;
  void project_at_footprint(const VelocityField& u, const std::vector<double>& p);
  void interpolate_projected(int c, const VelocityField& projected, Points& U) const;
  Eigen::VectorXd combination_;               // U = Σ combination_p z_p over those products
  detail::ParallelSpreading spreading_;       // the products' spreading schedule
  Eigen::MatrixXd basis_;                    // GMRES Krylov basis, sized once
  Eigen::MatrixXd arguments_;                // B⁻¹ of its vectors: the products' arguments
  int last_iterations_ = 0;
  bool fresh_in_step_ = false;              // this step's GMRES rebuilt the blocks at its own nodes
  int fresh_blocks_after_ = kFreshBlocksAfter;
  bool x1_invariant_ = true;
  bool several_ = false;  // more than one cell (or an uneven fluid): GMRES, its blocks only precondition
  Cost cost_;
  // GMRES's start (see solve_coupled): the node velocities U and right-hand sides U⁰ of the last two steps.
  Eigen::VectorXd last_U_, before_last_U_, last_rhs_, before_last_rhs_;
  // implicit_correction's phases, in order.
  Eigen::VectorXd predict(const std::vector<Cell>& cells, const VelocityField& u);  // U⁰ = J P u⁰
  void prepare_system(const std::vector<Cell>& cells);  // K_c and the preconditioner's blocks
  Eigen::VectorXd solve_system(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs);  // U
  void correct(const Eigen::VectorXd& U);  // correction_ = A⁻¹ S (−Δt K U)
  Eigen::VectorXd apply_full(const std::vector<Cell>& cells, const Eigen::VectorXd& v);
  Eigen::VectorXd solve_coupled(const std::vector<Cell>& cells, const Eigen::VectorXd& b);
  Eigen::VectorXd gmres(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs, const Eigen::VectorXd& x0, bool warm,
                        int max_it, double target, bool& converged);
};

}  // namespace rbc
