#include "semi_implicit/coupling_preconditioner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "membrane/membrane_stiffness.hpp"
#include "semi_implicit/detail/bf16_lu_solve.hpp"
#include "semi_implicit/detail/stopwatch.hpp"

namespace rbc {

Eigen::Matrix2d best_fit_rotation(const Points& from, const Points& to) {
  if (from.size() != to.size() || to.empty()) throw std::invalid_argument("best_fit_rotation: node counts differ");
  Eigen::Vector2d a = Eigen::Vector2d::Zero(), b = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < to.size(); ++i) {
    a += from[i];
    b += to[i];
  }
  a /= double(to.size());
  b /= double(to.size());
  double dot = 0, cross = 0;
  for (std::size_t i = 0; i < to.size(); ++i) {
    const Eigen::Vector2d p = from[i] - a, q = to[i] - b;
    dot += p.dot(q);
    cross += p.x() * q.y() - p.y() * q.x();
  }
  const double theta = std::atan2(cross, dot);
  Eigen::Matrix2d R;
  R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  return R;
}

CouplingPreconditioner::CouplingPreconditioner(StepMobility& mobility, const MembraneModel& model, double dt, bool turn_blocks)
    : mobility_(mobility), model_(model), dt_(dt), turn_blocks_(turn_blocks) {}

void CouplingPreconditioner::set_block_refresh_steps(int steps) { max_refresh_steps_ = refresh_steps_ = std::max(1, steps); }

void CouplingPreconditioner::prepare(const std::vector<Cell>& cells, const std::vector<MembraneStiffness>& stiffness, bool several,
                                     const Eigen::VectorXd& last_U, const std::vector<Eigen::Index>& offset) {
  // One cell's block is its whole system, built every step. Several: rebuilt every
  // refresh_steps_ steps, sooner after a hard step (after_solve), the interval growing back by
  // one at each rebuild that was due.
  const int ncells = int(cells.size());
  several_ = several;
  blocks_.resize(ncells);
  if (!several_) {
    block_nodes_.clear();
    factor_block(0, stiffness[0], cells[0].nodes);  // K at the cell's own nodes: the caller's
    ++block_builds_;
  } else if (int(block_nodes_.size()) != ncells || rebuild_now_ || steps_since_rebuild_ >= refresh_steps_) {
    if (!rebuild_now_ && int(block_nodes_.size()) == ncells) refresh_steps_ = std::min(max_refresh_steps_, refresh_steps_ + 1);
    rebuild_now_ = false;
    rebuild_all(cells, true, last_U, offset);
  } else {
    ++steps_since_rebuild_;
  }
  fit_turns(cells);
}

void CouplingPreconditioner::rebuild_fresh(const std::vector<Cell>& cells, const std::vector<Eigen::Index>& offset) {
  rebuild_all(cells, false, Eigen::VectorXd(), offset);
  fit_turns(cells);
  refresh_steps_ = std::max(1, refresh_steps_ / 2);
  ++fresh_rebuilds_;
}

void CouplingPreconditioner::after_solve(int iterations, bool fresh) {
  if (several_ && !fresh && iterations > rebuild_above_) {
    refresh_steps_ = std::max(1, refresh_steps_ / 2);
    rebuild_now_ = true;
  }
}

void CouplingPreconditioner::rebuild_all(const std::vector<Cell>& cells, bool ahead, const Eigen::VectorXd& last_U,
                                         const std::vector<Eigen::Index>& offset) {
  // Each block built where the cell's nodes will be halfway to the next rebuild (moving on with
  // the last step's velocities), then used for refresh_steps_ steps.
  const int ncells = int(cells.size());
  mobility_.prepare_phase_average(phase_average_extent(model_));
  const bool move = ahead && last_U.size() == offset[ncells];
  block_nodes_.resize(ncells);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c) {
    Points at = cells[c].nodes;
    if (move)
      for (std::size_t i = 0; i < at.size(); ++i)
        at[i] += 0.5 * refresh_steps_ * dt_ * Eigen::Vector2d(last_U[offset[c] + 2 * i], last_U[offset[c] + 2 * i + 1]);
    build_block(c, at, cells[c].target_area, cells[c].kb_scale);
    block_nodes_[c] = at;
  }
  block_builds_ += ncells;
  steps_since_rebuild_ = 1;
}

void CouplingPreconditioner::fit_turns(const std::vector<Cell>& cells) {
  // Each block's rotation onto its cell's nodes. None unless turned blocks are asked for and the
  // blocks only precondition.
  turn_.clear();
  if (!turn_blocks_ || !several_ || block_nodes_.size() != cells.size()) return;
  turn_.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) turn_[c] = best_fit_rotation(block_nodes_[c], cells[c].nodes);
}

Eigen::VectorXd CouplingPreconditioner::apply(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& offset) {
  detail::Stopwatch watch;
  Eigen::VectorXd out(v.size());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < int(blocks_.size()); ++c) {
    const Eigen::Index n = offset[c + 1] - offset[c];
    if (several_) {
      // x = B⁻¹ v: P B = L U, so L y = P v (unit diagonal), then U x = y (detail/bf16_lu_solve.hpp).
      // Turned blocks: x = R B⁻¹ Rᵀ v, node by node (see the header).
      const Block& b = blocks_[c];
      const int m = int(n);
      const double* in = v.data() + offset[c];
      thread_local std::vector<double> turned;
      const bool turn = !turn_.empty();
      if (turn) {
        const Eigen::Matrix2d& R = turn_[c];
        turned.resize(m);
        for (int i = 0; i < m; i += 2) {
          turned[i] = R(0, 0) * in[i] + R(1, 0) * in[i + 1];
          turned[i + 1] = R(0, 1) * in[i] + R(1, 1) * in[i + 1];
        }
        in = turned.data();
      }
      thread_local std::vector<float> x;
      x.resize(m);
      for (int i = 0; i < m; ++i) x[i] = float(in[b.permutation[i]]);
      detail::lu_solve_bf16(b.lu_bf16.data(), b.inverse_diagonal.data(), m, x.data());
      if (turn) {
        const Eigen::Matrix2d& R = turn_[c];
        for (int i = 0; i < m; i += 2) {
          out[offset[c] + i] = R(0, 0) * x[i] + R(0, 1) * x[i + 1];
          out[offset[c] + i + 1] = R(1, 0) * x[i] + R(1, 1) * x[i + 1];
        }
      } else {
        for (int i = 0; i < m; ++i) out[offset[c] + i] = x[i];
      }
    } else {
      out.segment(offset[c], n) = blocks_[c].lu.solve(v.segment(offset[c], n));
    }
  }
  watch.lap(apply_seconds_);
  return out;
}

void CouplingPreconditioner::build_block(int c, const Points& r, double target_area, double kb_scale) {
  // The cell's own system at nodes r (K and M both at r).
  factor_block(c, membrane_stiffness(model_of(model_, kb_scale), r, target_area), r);
}

void CouplingPreconditioner::factor_block(int c, const MembraneStiffness& K, const Points& r) {
  // I + Δt M_cc K_c, factored once; with several cells M̄_cc, M averaged over the cell's phase on
  // the grid along x1 (step_mobility.hpp).
  Eigen::MatrixXd M;
  if (several_)
    mobility_.phase_averaged_matrix(r, M);  // a preconditioner that a cell carried along x1 keeps
  else
    mobility_.matrix(r, M);
  Eigen::MatrixXd B = dt_ * K.right_multiply(M);
  B.diagonal().array() += 1.0;
  if (several_) {
    const Eigen::PartialPivLU<Eigen::MatrixXf> lu(B.cast<float>());
    Block& b = blocks_[c];
    detail::pack_lu_bf16(lu.matrixLU().data(), int(B.rows()), b.lu_bf16);
    b.inverse_diagonal.resize(B.rows());
    for (Eigen::Index i = 0; i < B.rows(); ++i) b.inverse_diagonal[i] = 1.0f / lu.matrixLU()(i, i);
    // P B = L U with P = lu.permutationP(): row i of P B is row p⁻¹(i) of B.
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse = lu.permutationP().inverse();
    b.permutation.assign(inverse.indices().data(), inverse.indices().data() + B.rows());
  } else {
    blocks_[c].lu.compute(B);
  }
}

void CouplingPreconditioner::save_schedule(CheckpointWriter& w) const {
  w.put(std::int64_t(steps_since_rebuild_));
  w.put(std::int64_t(refresh_steps_));
  w.put(std::int64_t(rebuild_now_));
}

void CouplingPreconditioner::load_schedule(CheckpointReader& r) {
  steps_since_rebuild_ = int(r.get_int());
  refresh_steps_ = int(r.get_int());
  if (refresh_steps_ < 1 || refresh_steps_ > max_refresh_steps_)
    throw CheckpointError(r.path() + ": preconditioner refresh interval " + std::to_string(refresh_steps_) + " out of range [1, " +
                          std::to_string(max_refresh_steps_) + "]");
  rebuild_now_ = r.get_int() != 0;
}

void CouplingPreconditioner::save_blocks(CheckpointWriter& w) const {
  w.put(std::int64_t(block_nodes_.size()));
  for (const Points& r : block_nodes_) w.put(r);
}

void CouplingPreconditioner::load_blocks(CheckpointReader& r, const std::vector<Cell>& cells, bool several) {
  const std::int64_t nblocks = r.get_int();
  if (nblocks != 0 && nblocks != std::int64_t(cells.size()))
    throw CheckpointError(r.path() + ": preconditioner blocks for " + std::to_string(nblocks) + " cells, the scene has " +
                          std::to_string(cells.size()));
  block_nodes_.resize(std::size_t(nblocks));
  for (std::size_t c = 0; c < block_nodes_.size(); ++c)
    block_nodes_[c] = r.get_points(cells[c].nodes.size(), "the nodes of a preconditioner block");
  // The blocks as the uninterrupted run has them (built from the same nodes the same way).
  several_ = several;
  if (several_ && !block_nodes_.empty()) mobility_.prepare_phase_average(phase_average_extent(model_));
  blocks_.resize(block_nodes_.size());
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < int(block_nodes_.size()); ++c) build_block(c, block_nodes_[c], cells[c].target_area, cells[c].kb_scale);
}

}  // namespace rbc
