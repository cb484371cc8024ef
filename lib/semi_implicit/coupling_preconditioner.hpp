#pragma once
// The preconditioner of the semi-implicit coupling's cell-to-cell system (semi_implicit_coupling.hpp):
//
//   B = blockdiag(I + Δt M_cc K_c),   one block per cell c,
//
// each cell's own system: K_c its membrane stiffness (membrane_stiffness.hpp), M_cc the step
// mobility of its own nodes (step_mobility.hpp). GMRES then iterates only on what couples the
// cells through the fluid.
//
// One cell in a fluid invariant along x1: its block is its whole system, built with the exact M
// at every step and factored in double (apply() then solves it).
//
// Several cells (or a fluid made uneven by obstacles or disks): the blocks only precondition, so
//   - they are built from M̄, M averaged over the cell's phase on the grid along x1
//     (StepMobility::phase_averaged_matrix), which a cell carried by the flow keeps;
//   - they are factored in single precision and stored in bfloat16 (detail/bf16_lu_solve.hpp);
//   - they are rebuilt every refresh_steps() steps, at most kBlockRefreshSteps: the interval halves
//     after a step that needed more than kRebuildAboveIterations GMRES iterations or fresh blocks
//     (then rebuilt at the next step), and grows back by one at each rebuild that was due;
//   - they are built where the nodes will be halfway to the next rebuild (moved on with the last
//     step's node velocities);
//   - turned blocks (CouplingOptions::turn_blocks): a cell that has turned by R since its block
//     was built gets R B⁻¹ Rᵀ, R the best-fit rotation of its nodes (best_fit_rotation).
// paper/method/04_semi_implicit_coupling.md explains each rule and what it saves.
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "io/checkpoint.hpp"
#include "semi_implicit/step_mobility.hpp"
#include "membrane/cell.hpp"
#include "membrane/membrane_stiffness.hpp"
#include "membrane/spring_membrane.hpp"

namespace rbc {

// The rotation R that best maps the nodes `from` onto `to` about their centroids (least squares,
// 2D): θ = atan2(Σ_i p_i × q_i, Σ_i p_i · q_i), p_i = from_i − mean(from), q_i = to_i − mean(to).
// Same number of nodes.
Eigen::Matrix2d best_fit_rotation(const Points& from, const Points& to);

class CouplingPreconditioner {
 public:
  static constexpr int kBlockRefreshSteps = 30;       // longest rebuild interval, steps
  static constexpr int kRebuildAboveIterations = 12;  // a step above this: rebuild sooner

  CouplingPreconditioner(StepMobility& mobility, const MembraneModel& model, double dt, bool turn_blocks);

  // At the start of a step, before the solve: the blocks it uses. several: the blocks only
  // precondition (see above); otherwise cell 0's block is its whole system, built at its nodes.
  // stiffness: each cell's K at its nodes now (one cell's block is built from it); last_U, offset:
  // the last step's node velocities and each cell's first unknown (building ahead).
  void prepare(const std::vector<Cell>& cells, const std::vector<MembraneStiffness>& stiffness, bool several,
               const Eigen::VectorXd& last_U, const std::vector<Eigen::Index>& offset);
  // B⁻¹ v (turned where asked).
  Eigen::VectorXd apply(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& offset);
  // GMRES did not converge with the blocks as they are: rebuild them at the step's own nodes, and
  // rebuild more often from now on.
  void rebuild_fresh(const std::vector<Cell>& cells, const std::vector<Eigen::Index>& offset);
  // After the solve: a step that needed more than the rebuild threshold's iterations (and no
  // fresh blocks) has the blocks rebuilt at the next step and the interval halved.
  void after_solve(int iterations, bool fresh);

  // For tests and measurements: the longest interval and the threshold.
  void set_block_refresh_steps(int steps);
  void set_rebuild_above_iterations(int iterations) { rebuild_above_ = iterations; }
  int refresh_steps() const { return refresh_steps_; }

  // Counters (since construction): blocks built, fresh rebuilds, seconds in apply().
  long block_builds() const { return block_builds_; }
  long fresh_rebuilds() const { return fresh_rebuilds_; }
  double apply_seconds() const { return apply_seconds_; }

  // Checkpoints: the rebuild schedule, then the nodes the blocks were built at. load_blocks
  // rebuilds the blocks from those nodes, so a resumed run takes the same steps bit for bit.
  void save_schedule(CheckpointWriter& w) const;
  void load_schedule(CheckpointReader& r);
  void save_blocks(CheckpointWriter& w) const;
  void load_blocks(CheckpointReader& r, const std::vector<Cell>& cells, bool several);

 private:
  struct Block {
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // one cell: its whole system, in double
    // Several cells: P B = L U in single precision, L and U in bfloat16 in the order the sweep
    // reads them (detail/bf16_lu_solve.hpp), 1/U_ii in float and P as indices.
    std::vector<std::uint16_t> lu_bf16;
    std::vector<float> inverse_diagonal;
    std::vector<int> permutation;  // row i of P B is row permutation[i] of B
  };
  void build_block(int c, const Points& r, double target_area, double kb_scale);  // K at r, then factor_block
  void factor_block(int c, const MembraneStiffness& K, const Points& r);
  void rebuild_all(const std::vector<Cell>& cells, bool ahead, const Eigen::VectorXd& last_U, const std::vector<Eigen::Index>& offset);
  void fit_turns(const std::vector<Cell>& cells);

  StepMobility& mobility_;
  MembraneModel model_;
  double dt_;
  bool turn_blocks_;
  bool several_ = false;
  std::vector<Block> blocks_;
  std::vector<Points> block_nodes_;    // the nodes the blocks were last built at (ahead of the cells)
  std::vector<Eigen::Matrix2d> turn_;  // each block's rotation onto its cell's nodes (empty: none)
  int steps_since_rebuild_ = 0;
  int max_refresh_steps_ = kBlockRefreshSteps;
  int refresh_steps_ = kBlockRefreshSteps;
  bool rebuild_now_ = false;
  int rebuild_above_ = kRebuildAboveIterations;
  long block_builds_ = 0, fresh_rebuilds_ = 0;
  double apply_seconds_ = 0;
};

}  // namespace rbc
