#pragma once
// The semi-implicit coupling ("semi-implicit" in scenes; issue 4): the study's scheme with the
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
// and u^{n+1} = u⁰ + A⁻¹ S (−Δt K U): one more fast solve per step (with several cells not even
// that: U is a combination of GMRES's product arguments, whose responses A⁻¹ S K z it keeps).
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
#include "immersed_boundary/coupling_products.hpp"
#include "immersed_boundary/explicit_coupling.hpp"
#include "immersed_boundary/immersed_boundary.hpp"
#include "immersed_boundary/step_mobility.hpp"
#include "membrane/membrane_stiffness.hpp"

namespace rbc {

// The rotation R that best maps the nodes `from` onto `to` about their centroids (least squares;
// "Turned blocks" above): θ = atan2(Σ p × q, Σ p · q). Same number of nodes.
Eigen::Matrix2d best_fit_rotation(const Points& from, const Points& to);

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
};

// The options in words, e.g. "start constant, blocks turned, products single where possible"
// (summary.json records it; --reuse compares it).
std::string describe(const CouplingOptions& options);

class SemiImplicitMembraneStep {
 public:
  using Start = CouplingOptions::Start;
  // tolerance: relative residual of the cell-to-cell GMRES solve (several cells).
  SemiImplicitMembraneStep(ChannelFlow& flow, const MembraneModel& model, double tolerance = 1e-4, const CouplingOptions& options = {});
  // Step 2 (the study's): move the nodes with u^{n+1/3}, spread F^{n+1} for step 4.
  const VelocityField& step(std::vector<Cell>& cells, const VelocityField& u, double dt) { return move_.step(cells, u, dt); }
  // Step 2's mover (the scene's membrane repulsion is set on it).
  ExplicitMembraneStep& membrane_move() { return move_; }
  // After step 4 with F^{n+1}: u = u⁰ in (not changed); returns the velocity change A⁻¹ S (−Δt K U)
  // (m/s, zero on the walls) that turns u⁰ into u^{n+1}: step 4's response to the implicit force.
  const VelocityField& implicit_correction(const std::vector<Cell>& cells, const VelocityField& u);
  int last_iterations() const { return last_iterations_; }
  // The fluid is no longer invariant under shifts in x1 (an obstacle's multiplier in step 4): the
  // tabulated mobility is then only a preconditioner, and even one cell goes through GMRES, whose
  // products (spread, step 4, project, interpolate) are exact. Call it after the constraint is
  // installed in step 4 (the products' solves are chosen then).
  void set_fluid_not_x1_invariant();
  // Checkpoints: the projection's warm start, GMRES's starting point and the nodes the current
  // preconditioner blocks were built at (load rebuilds them from those nodes, so a resumed run
  // takes the same steps bit for bit).
  void save(CheckpointWriter& w) const;
  void load(CheckpointReader& r, const std::vector<Cell>& cells);
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

  // GMRES: at most kFreshBlocksAfter iterations with the blocks as they are; if that does not
  // converge, the blocks are rebuilt at the nodes of the step and GMRES goes on from its last
  // iterate for at most kCouplingMaxIterations more (then the run stops). A step that needed more
  // than kRebuildAboveIterations has the blocks rebuilt at the next step and the interval halved.
  // Neither triggers at Δt = 2e-6 s in the benchmark's 100-cell flow (at most 11 iterations a
  // step, at its first steps); they keep larger steps going, whose blocks go stale sooner (100
  // cells in the developed flow with only the fixed interval: GMRES did not converge in 60
  // iterations at step 7 with Δt = 4e-6 s, at step 3 with 6e-6 s).
  static constexpr int kCouplingMaxIterations = 60;
  static constexpr int kFreshBlocksAfter = 20;
  static constexpr int kRebuildAboveIterations = 12;
  // For tests: fresh blocks after this many iterations instead (0: at every step).
  void set_fresh_blocks_after(int iterations) { fresh_blocks_after_ = iterations; }
  // For tests: the blocks rebuilt after a step with more than this many iterations instead.
  void set_rebuild_above_iterations(int iterations) { rebuild_above_ = iterations; }
  // For measurements: the blocks' rebuild interval (steps, at most; default kBlockRefreshSteps).
  void set_block_refresh_steps(int steps) { max_refresh_steps_ = refresh_steps_ = std::max(1, steps); }
  // Several cells: preconditioner blocks rebuilt every 30 steps at most (see refresh_steps_).
  // What made blocks of the exact M go stale within a few steps was the grid phase: a block of M
  // built 0.27 h upstream of where the cell is gave ‖B_old⁻¹ B_new − I‖ ≈ 2.8 (rms per unknown),
  // the same block with the old K and the new M 4e-4 (100 cells, wide grid, 2e-6 s: iterations
  // from 3 to 7-8 within 10 steps of a rebuild). The blocks are therefore built from M̄, M
  // averaged over the cell's phase along x1 (step_mobility.hpp), which a cell carried by the
  // flow keeps; what still ages them is the cells deforming, turning and drifting across.
  // Measured, 100 cells in the developed flow, 300 steps, products per step for a rebuild every
  // 5 / 10 / 15 / 20 / 30 / 40 steps: 3.32 / 3.35 / 3.39 / 3.42 / 3.71 / 3.94 at 1.2e-6 s and
  // 4.04 / 4.20 / 4.33 / 4.53 / 4.77 (to 30) at 2e-6 s, against 4.1 at 1.2e-6 s and 5.8 at
  // 2e-6 s with blocks of M every 10 steps. With a build at ≈ 0.27 ms and a product with its
  // preconditioner sweep at ≈ 1.1 ms (2 threads), 30 steps cost least (4.9 ms a step against 5.1
  // for 20 and 5.0 for 40; paper/method/04_semi_implicit_coupling.md). Blocks are still built
  // where the nodes will be halfway to the next rebuild (kBuildAhead; without it 3.64 against
  // 3.42 products at 1.2e-6 s, 5.36 against 4.53 at 2e-6 s, both with a rebuild every 20 steps).
  static constexpr int kBlockRefreshSteps = 30;

 private:
  ChannelFlow& flow_;
  double tolerance_;
  ChannelMesh mesh_;
  MembraneModel model_;
  double dt_;
  VelocityField projected_;             // P u⁰
  std::vector<double> pressure_;        // its pressure, the warm start of the next predictor
  ExplicitMembraneStep move_;
  StepMobility mobility_;
  VelocityField correction_;
  // The coupled system of the current step.
  struct Block {
    MembraneStiffness K;                  // the cell's stiffness
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;         // of I + Δt M_cc K_c: one cell (its whole system)
    // Several cells (a preconditioner): the same factored in single precision, P B = L U, with
    // L and U in bfloat16 in the order the sweep reads them (bf16_lu_solve.hpp), 1/U_ii in float
    // and P as indices.
    std::vector<std::uint16_t> lu_bf16;
    std::vector<float> inverse_diagonal;
    std::vector<int> permutation;  // row i of P B is row permutation[i] of B
  };
  std::vector<Block> blocks_;
  std::vector<Eigen::Index> offset_;  // first unknown of each cell
  CouplingOptions options_;
  std::unique_ptr<CouplingProducts> products_;  // the products' fluid solves (several cells or obstacles)
  VelocityField work_;                        // GMRES matrix-vector product: the velocity
  Eigen::VectorXd kv_;                        // and K v, the nodes' forces it spreads
  std::vector<VelocityField> responses_;      // A⁻¹ S K z of this step's products, in order
  int products_in_step_ = 0;
  Eigen::VectorXd combination_;               // U = Σ combination_p z_p over those products
  static constexpr int kSpreadSlabs = 4;       // x1 slabs of the products' spreading (even: two phases)
  std::vector<std::vector<int>> slab_cells_;  // the cells of each slab (empty: per-thread arrays)
  std::vector<std::vector<double>> thread_rhs_;  // threads 1.. of the per-thread spreading (both components)
  Eigen::MatrixXd basis_;                    // GMRES Krylov basis, sized once
  Eigen::MatrixXd arguments_;                // B⁻¹ of its vectors: the products' arguments
  int last_iterations_ = 0;
  int steps_since_rebuild_ = 0;
  int max_refresh_steps_ = kBlockRefreshSteps;
  int refresh_steps_ = kBlockRefreshSteps;  // the blocks' current rebuild interval (see implicit_correction)
  bool rebuild_now_ = false;                // rebuild at the next step
  bool fresh_in_step_ = false;              // this step's GMRES rebuilt the blocks at its own nodes
  int fresh_blocks_after_ = kFreshBlocksAfter;
  int rebuild_above_ = kRebuildAboveIterations;
  bool x1_invariant_ = true;
  bool several_ = false;  // more than one cell: blocks in single precision, GMRES
  Cost cost_;
  // GMRES's start (see solve_coupled): the node velocities U and right-hand sides U⁰ of the last two steps.
  Eigen::VectorXd last_U_, before_last_U_, last_rhs_, before_last_rhs_;
  static constexpr bool kBuildAhead = true;  // see kBlockRefreshSteps
  std::vector<Points> block_nodes_;  // the nodes the blocks were last built at (ahead of the cells)
  std::vector<Eigen::Matrix2d> turn_;  // each block's rotation onto its cell's nodes (options_.turn_blocks; empty: none)
  void fit_turns(const std::vector<Cell>& cells);
  void build_block(int c, const Points& r, double target_area, double kb_scale);
  Eigen::VectorXd apply_full(const std::vector<Cell>& cells, const Eigen::VectorXd& v);
  Eigen::VectorXd precondition(const Eigen::VectorXd& v);
  Eigen::VectorXd solve_coupled(const std::vector<Cell>& cells, const Eigen::VectorXd& b);
  Eigen::VectorXd gmres(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs, const Eigen::VectorXd& x0, bool warm,
                        int max_it, double target, bool& converged);
  void rebuild_blocks(const std::vector<Cell>& cells, bool ahead);
};

}  // namespace rbc
