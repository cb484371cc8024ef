#include "immersed_boundary/semi_implicit_coupling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <omp.h>

#include "immersed_boundary/bf16_lu_solve.hpp"
#include "immersed_boundary/immersed_boundary.hpp"

namespace rbc {

SemiImplicitMembraneStep::SemiImplicitMembraneStep(ChannelFlow& flow, const MembraneModel& model, double tolerance,
                                                   const CouplingOptions& options)
    : flow_(flow),
      tolerance_(tolerance),
      mesh_(flow.mesh()),
      model_(model),
      dt_(flow.params().dt),
      projected_(flow.mesh()),
      pressure_(flow.mesh().pressure_nodes(), 0.0),
      move_(flow.mesh(), model),
      mobility_(flow.mesh(), flow.diffusion(), flow.projection(), flow.params().fluid.density, flow.params().dt),
      correction_(flow.mesh()),
      options_(options),
      work_(flow.mesh()) {}

std::string describe(const CouplingOptions& o) {
  return std::string("start ") + (o.start == CouplingOptions::Start::kConstant ? "constant" : "linear") + ", blocks " +
         (o.turn_blocks ? "turned" : "fixed") + ", products " +
         (o.product_precision == CouplingProducts::Precision::kDouble ? "double" : "single where possible");
}

void SemiImplicitMembraneStep::set_fluid_not_x1_invariant() {
  x1_invariant_ = false;
  products_.reset();  // chosen again for the constrained step 4
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Points as_points(const Eigen::VectorXd& v, Eigen::Index offset, int n) {
  Points p(n);
  for (int i = 0; i < n; ++i) p[i] = Eigen::Vector2d(v[offset + 2 * i], v[offset + 2 * i + 1]);
  return p;
}
}  // namespace

Eigen::VectorXd SemiImplicitMembraneStep::apply_full(const std::vector<Cell>& cells, const Eigen::VectorXd& v) {
  // (I + Δt M K) v with M = J P A⁻¹ S over all cells at once, the long way (exact).
  const auto t0 = std::chrono::steady_clock::now();
  ++cost_.product_count;
  const int ncells = int(cells.size());
  // h² S K v, spread straight into step 4's right-hand sides (weights φ_x φ_y: S has 1/h²).
  // K v first, every cell on its own (shared evenly by the threads), then the spreading, whose
  // shares follow the cells' places (below).
  const int nx = mesh_.nx, ny = mesh_.ny;
  kv_.resize(v.size());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < ncells; ++c) {
    const Eigen::Index n = offset_[c + 1] - offset_[c];
    kv_.segment(offset_[c], n) = blocks_[c].K.apply(v.segment(offset_[c], n));
  }
  auto spread = [&](int c, double* f1, double* f2) {
    spread_forces_interior(mesh_, move_.stencils()[c], kv_.data() + offset_[c], f1, f2);
  };
  if (!products_)
    products_ = std::make_unique<CouplingProducts>(mesh_, flow_.diffusion(), flow_.projection(), flow_.params().fluid.density, dt_,
                                                   options_.product_precision);
  auto [f1, f2] = products_->force_rhs();
  if (!slab_cells_.empty()) {
    // Cells in x1 slabs (see implicit_correction): the even slabs' cells touch disjoint mesh
    // nodes, so their threads add into the same arrays; then the odd slabs'. Every node sums its
    // cells in the same order whatever the thread count.
    for (int phase = 0; phase < 2; ++phase) {
#pragma omp parallel for schedule(static, 1)
      for (int s = phase; s < int(slab_cells_.size()); s += 2)
        for (int c : slab_cells_[s]) spread(c, f1, f2);
    }
  } else {
    // Otherwise each thread spreads its share of the cells (a fixed share: the sum is the same
    // from run to run for a given thread count) into its own arrays, added in thread order.
    const int threads = std::max(1, std::min(omp_get_max_threads(), ncells));
    const std::size_t size = std::size_t(nx) * (ny - 1);
    if (int(thread_rhs_.size()) != threads - 1) thread_rhs_.assign(threads - 1, std::vector<double>(2 * size));
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num();
      double* g1 = t == 0 ? f1 : thread_rhs_[t - 1].data();
      double* g2 = t == 0 ? f2 : thread_rhs_[t - 1].data() + size;
      if (t > 0) std::fill(thread_rhs_[t - 1].begin(), thread_rhs_[t - 1].end(), 0.0);
      for (int c = t * ncells / threads; c < (t + 1) * ncells / threads; ++c) spread(c, g1, g2);
    }
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(size); ++k)
      for (int t = 1; t < threads; ++t) {
        f1[k] += thread_rhs_[t - 1][k];
        f2[k] += thread_rhs_[t - 1][size + k];
      }
  }
  cost_.product_spread += seconds_since(t0);
  // A⁻¹ S K v, kept for the correction (u^{n+1} − u⁰ is a combination of these), then P.
  if (int(responses_.size()) <= products_in_step_) responses_.emplace_back(mesh_);
  VelocityField& response = responses_[products_in_step_++];
  const auto t1 = std::chrono::steady_clock::now();
  products_->response(response);
  cost_.product_solve += seconds_since(t1);
  const auto t2 = std::chrono::steady_clock::now();
  products_->project(response, work_);
  cost_.product_project += seconds_since(t2);
  Eigen::VectorXd out = v;
#pragma omp parallel for schedule(static)
  for (int c = 0; c < ncells; ++c) {  // out += Δt J P A⁻¹ S K v
    thread_local Points U;
    interpolate_velocity(mesh_, work_, move_.stencils()[c], U);
    for (std::size_t k = 0; k < U.size(); ++k) {
      out[offset_[c] + 2 * k] += dt_ * U[k].x();
      out[offset_[c] + 2 * k + 1] += dt_ * U[k].y();
    }
  }
  cost_.products += seconds_since(t0);
  return out;
}

Eigen::VectorXd SemiImplicitMembraneStep::precondition(const Eigen::VectorXd& v) {
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::VectorXd out(v.size());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < int(blocks_.size()); ++c) {
    const Eigen::Index n = offset_[c + 1] - offset_[c];
    if (several_)
    {
      // x = B⁻¹ v: P B = L U, so L y = P v (unit diagonal), then U x = y (bf16_lu_solve.hpp).
      // Turned blocks: x = R B⁻¹ Rᵀ v, node by node (see the header).
      const Block& b = blocks_[c];
      const int m = int(n);
      const double* in = v.data() + offset_[c];
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
          out[offset_[c] + i] = R(0, 0) * x[i] + R(0, 1) * x[i + 1];
          out[offset_[c] + i + 1] = R(1, 0) * x[i] + R(1, 1) * x[i + 1];
        }
      } else {
        for (int i = 0; i < m; ++i) out[offset_[c] + i] = x[i];
      }
    }
    else
      out.segment(offset_[c], n) = blocks_[c].lu.solve(v.segment(offset_[c], n));
  }
  cost_.preconditioner += seconds_since(t0);
  return out;
}

Eigen::VectorXd SemiImplicitMembraneStep::solve_coupled(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs) {
  // GMRES on (I + Δt M K) B⁻¹ y = b, U = B⁻¹ y, with B = blockdiag(I + Δt M_cc K_c): each cell's
  // own system (exact, from StepMobility), so only the cell-to-cell coupling is left to iterate.
  // Started near the solution (node velocities change little from step to step): we solve for
  // the change, with the tolerance still relative to the full right-hand side. The linear start
  // (Start::kLinear) takes the last two steps' U on in a straight line, plus the cells' own
  // response B⁻¹ to the part of the right-hand side that the straight line does not predict,
  //
  //   x0 = 2 Uⁿ − Uⁿ⁻¹ + B⁻¹ (b − 2 bⁿ + bⁿ⁻¹)      (x0 = Uⁿ + B⁻¹ (b − bⁿ) at the second step):
  //
  // the nodes' velocities U⁰ jitter from step to step as they cross mesh lines, and the stiff
  // membrane modes follow that jitter at once, which no extrapolation can; their own system does
  // (measured, 100 cells in the developed flow, 100 steps: initial residual ≈ 1e-2 → 2–6e-3 of
  // ‖b‖, 6.8 → 5.8 products per step; a quadratic extrapolation with the third difference of b
  // did worse, 6.5). The constant start (Start::kConstant) is the second step's form at every
  // step, x0 = Uⁿ + B⁻¹ (b − bⁿ). What the start misses is mostly the last solve's own error,
  // grown about a hundredfold by one step (the starting residual is ≈ 100 times the tolerance
  // at 1e-4 and 1e-3, measured at 3e-6 s): a straight line through two solutions carries two
  // such errors, and at larger Δt the trend it follows is worth less than that. Measured
  //: GMRES
  // iterations per step 8.47 → 7.74 (50 cells, seed 1), 7.58 → 6.89 (seed 2), 10.95 → 10.00
  // (seed 3), 8.70 → 8.55, 8.47 → 8.15, 8.47 → 8.19 (100 cells, seeds 1–3), with 3–38 % fewer
  // block rebuilds. From rest in the developed profile, the cells still accelerating, the
  // straight line does better (100 cells: 4.1 against 6.2 products a step at 1.2e-6 s, 6.7
  // against 7.5 at 2e-6 s), so it stays the default (paper/method/04_semi_implicit_coupling.md).
  const bool warm = last_U_.size() == rhs.size() && last_rhs_.size() == rhs.size();
  Eigen::VectorXd x0;
  if (warm && options_.start == Start::kLinear && before_last_U_.size() == rhs.size() && before_last_rhs_.size() == rhs.size())
    x0 = 2.0 * last_U_ - before_last_U_ + precondition(rhs - 2.0 * last_rhs_ + before_last_rhs_);
  else if (warm)
    x0 = last_U_ + precondition(rhs - last_rhs_);
  const double target = tolerance_ * rhs.norm();
  last_iterations_ = 0;
  bool converged = false;
  Eigen::VectorXd U = gmres(cells, rhs, x0, warm, fresh_blocks_after_, target, converged);
  if (!converged) {
    // The blocks have gone too stale for this Δt (the cells moved further than they were built
    // ahead for): rebuild them at the nodes of this step and go on from where GMRES got to.
    const auto t0 = std::chrono::steady_clock::now();
    rebuild_blocks(cells, false);
    fit_turns(cells);
    refresh_steps_ = std::max(1, refresh_steps_ / 2);
    fresh_in_step_ = true;
    ++cost_.fresh_rebuilds;
    const double seconds = seconds_since(t0);  // counted as blocks, not as the coupled solve
    cost_.blocks += seconds;
    cost_.coupled -= seconds;
    U = gmres(cells, rhs, U, true, kCouplingMaxIterations, target, converged);
    if (!converged)
      throw std::runtime_error("semi-implicit coupling: the cell-to-cell system did not converge in " +
                               std::to_string(fresh_blocks_after_) + " + " + std::to_string(kCouplingMaxIterations) +
                               " GMRES iterations (the second run with blocks built at the nodes of this step)");
  }
  return U;
}

Eigen::VectorXd SemiImplicitMembraneStep::gmres(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs,
                                                const Eigen::VectorXd& x0, bool warm, int max_it, double target,
                                                bool& converged) {
  // One GMRES run of at most max_it iterations from x0 (0 if not warm); returns its last iterate.
  const Eigen::VectorXd b = warm ? Eigen::VectorXd(rhs - apply_full(cells, x0)) : rhs;
  // U = x0 + Z y is a combination of the products' arguments, so that the correction is the same
  // combination of their responses: x0 is the argument of the product just made (if warm), the
  // products of an earlier run drop out.
  combination_ = Eigen::VectorXd::Zero(products_in_step_);
  if (warm) combination_[products_in_step_ - 1] = 1.0;
  const double bnorm = b.norm();
  converged = bnorm <= target;
  if (converged) return warm ? x0 : Eigen::VectorXd(Eigen::VectorXd::Zero(rhs.size()));
  if (basis_.rows() != b.size() || basis_.cols() < max_it + 1) {
    basis_.resize(b.size(), max_it + 1);
    arguments_.resize(b.size(), max_it);
  }
  Eigen::MatrixXd& V = basis_;
  Eigen::MatrixXd& Z = arguments_;  // B⁻¹ v_k, the products' arguments
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(max_it + 1, max_it);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(max_it + 1), cs(max_it), sn(max_it);
  V.col(0) = b / bnorm;
  g[0] = bnorm;
  int k = 0;
  for (; k < max_it; ++k) {
    Z.col(k) = precondition(V.col(k));
    Eigen::VectorXd w = apply_full(cells, Z.col(k));
    for (int i = 0; i <= k; ++i) {  // modified Gram–Schmidt
      H(i, k) = V.col(i).dot(w);
      w -= H(i, k) * V.col(i);
    }
    H(k + 1, k) = w.norm();
    if (H(k + 1, k) > 0) V.col(k + 1) = w / H(k + 1, k);
    for (int i = 0; i < k; ++i) {  // previous Givens rotations
      const double t = cs[i] * H(i, k) + sn[i] * H(i + 1, k);
      H(i + 1, k) = -sn[i] * H(i, k) + cs[i] * H(i + 1, k);
      H(i, k) = t;
    }
    const double rr = std::hypot(H(k, k), H(k + 1, k));
    cs[k] = H(k, k) / rr;
    sn[k] = H(k + 1, k) / rr;
    H(k, k) = rr;
    H(k + 1, k) = 0;
    g[k + 1] = -sn[k] * g[k];
    g[k] = cs[k] * g[k];
    ++last_iterations_;
    if (std::abs(g[k + 1]) <= target) {
      converged = true;
      ++k;
      break;
    }
  }
  const Eigen::VectorXd y = H.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  Eigen::VectorXd U = Z.leftCols(k) * y;
  if (warm) U += x0;
  combination_.conservativeResize(combination_.size() + k);
  combination_.tail(k) = y;
  return U;
}

void SemiImplicitMembraneStep::rebuild_blocks(const std::vector<Cell>& cells, bool ahead) {
  // Several cells: each block built where the cell's nodes will be halfway to the next rebuild
  // (moving on with the last step's velocities), then used for refresh_steps_ steps.
  const int ncells = int(cells.size());
  mobility_.prepare_phase_average(phase_average_extent(model_));
  const bool move = ahead && kBuildAhead && last_U_.size() == offset_[ncells];
  block_nodes_.resize(ncells);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c) {
    Points at = cells[c].nodes;
    if (move)
      for (std::size_t i = 0; i < at.size(); ++i)
        at[i] += 0.5 * refresh_steps_ * dt_ * Eigen::Vector2d(last_U_[offset_[c] + 2 * i], last_U_[offset_[c] + 2 * i + 1]);
    build_block(c, at, cells[c].target_area, cells[c].kb_scale);
    block_nodes_[c] = at;
  }
  cost_.block_builds += ncells;
  steps_since_rebuild_ = 1;
}

const VelocityField& SemiImplicitMembraneStep::implicit_correction(const std::vector<Cell>& cells, const VelocityField& u) {
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  ++cost_.steps;
  products_in_step_ = 0;
  const int ncells = int(cells.size());
  offset_.assign(ncells + 1, 0);
  for (int c = 0; c < ncells; ++c) offset_[c + 1] = offset_[c] + 2 * Eigen::Index(cells[c].nodes.size());
  // P u⁰: the velocity step 1 would hand to step 2 without the correction; U⁰ = J P u⁰ at the
  // nodes, unknowns (x_1, y_1, x_2, …).
  // (Several cells: the projection as the products make it, without CG's residual checks; with
  // the exact Schur preconditioner project() takes that one iteration too, and one-cell runs keep
  // project(), bit for bit as before.)
  if (ncells > 1) {
    flow_.projection().project_exact(u, projected_, flow_.params().fluid.density, dt_);
  } else {
    projected_ = u;
    flow_.projection().project(projected_, pressure_, flow_.params().fluid.density, dt_);
  }
  // The nodes' stencils at r^{n+1}: step 2 made them to spread F^{n+1}.
  const auto& stencils = move_.stencils();
  if (stencils.size() != cells.size()) throw std::logic_error("semi-implicit coupling: implicit_correction without step");
  Eigen::VectorXd rhs(offset_[ncells]);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c) {
    Points U0;
    interpolate_velocity(mesh_, projected_, stencils[c], U0);
    rhs.segment(offset_[c], offset_[c + 1] - offset_[c]) = Eigen::Map<const Eigen::VectorXd>(U0[0].data(), 2 * U0.size());
  }
  // Slabs for the products' spreading: the channel cut into kSpreadSlabs equal slabs along x1,
  // each cell in the slab of its mean x1. Used when no cell reaches further than half a slab
  // from its mean (its stencils and a mesh cell of margin included), so that slabs two apart
  // never touch the same nodes; otherwise (narrow channels) the per-thread arrays.
  slab_cells_.clear();
  if (ncells > 1) {
    const double slab = mesh_.length / kSpreadSlabs;
    double reach = 0;
    std::vector<double> mean(ncells);
    for (int c = 0; c < ncells; ++c) {
      double sum = 0;
      for (const auto& r : cells[c].nodes) sum += r.x();
      mean[c] = sum / double(cells[c].nodes.size());
      for (const auto& r : cells[c].nodes) reach = std::max(reach, std::abs(r.x() - mean[c]));
    }
    if (2 * (reach + 3 * mesh_.h) < slab) {
      slab_cells_.resize(kSpreadSlabs);
      for (int c = 0; c < ncells; ++c) {
        const double x = mean[c] - mesh_.length * std::floor(mean[c] / mesh_.length);
        slab_cells_[std::min(kSpreadSlabs - 1, int(x / slab))].push_back(c);
      }
    }
  }
  cost_.predictor += seconds_since(t0);
  t0 = clock::now();
  // With several cells the blocks only precondition GMRES (the matrix-vector product is exact),
  // so they are rebuilt every refresh_steps_ steps: kBlockRefreshSteps, halved after a step that
  // needed more than kRebuildAboveIterations iterations or fresh blocks (rebuilt at the next step),
  // and grown back by one at each rebuild that was due. One cell's block is its whole system,
  // built every step.
  several_ = ncells > 1 || !x1_invariant_;
  blocks_.resize(ncells);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c)  // at r^{n+1}: the system's K
    blocks_[c].K = membrane_stiffness(model_of(model_, cells[c].kb_scale), cells[c].nodes, cells[c].target_area);
  if (!several_) {
    block_nodes_.clear();
    build_block(0, cells[0].nodes, cells[0].target_area, cells[0].kb_scale);
    ++cost_.block_builds;
  } else if (int(block_nodes_.size()) != ncells || rebuild_now_ || steps_since_rebuild_ >= refresh_steps_) {
    if (!rebuild_now_ && int(block_nodes_.size()) == ncells) refresh_steps_ = std::min(max_refresh_steps_, refresh_steps_ + 1);
    rebuild_now_ = false;
    rebuild_blocks(cells, true);
  } else {
    ++steps_since_rebuild_;
  }
  fit_turns(cells);
  cost_.blocks += seconds_since(t0);
  t0 = clock::now();
  // One cell in an x1-invariant fluid: its own system is the whole system. Several, or a fluid
  // with obstacles (the block, from the obstacle-free mobility, is then only a preconditioner):
  // the coupled solve. (Before a fix, one cell with obstacles took the block's solution as
  // exact, and the step blew up within four steps.)
  last_iterations_ = 0;
  fresh_in_step_ = false;
  const Eigen::VectorXd U = several_ ? solve_coupled(cells, rhs) : precondition(rhs);
  // A step that needed many iterations: the blocks go stale faster than the interval assumes (a
  // larger Δt, faster cells), so they are rebuilt at the next step and more often from then on.
  if (several_ && !fresh_in_step_ && last_iterations_ > rebuild_above_) {
    refresh_steps_ = std::max(1, refresh_steps_ / 2);
    rebuild_now_ = true;
  }
  before_last_U_ = last_U_;
  last_U_ = U;
  before_last_rhs_ = last_rhs_;
  last_rhs_ = rhs;
  cost_.coupled += seconds_since(t0);
  t0 = clock::now();
  // Step 4's response to ΔF = −Δt K U, the change of the spring force over the coming step.
  std::fill(correction_.u1.begin(), correction_.u1.end(), 0.0);
  std::fill(correction_.u2.begin(), correction_.u2.end(), 0.0);
  if (!several_) {  // spread ΔF and solve
    VelocityField& force = work_;
    std::fill(force.u1.begin(), force.u1.end(), 0.0);
    std::fill(force.u2.begin(), force.u2.end(), 0.0);
    const Eigen::VectorXd f = -dt_ * blocks_[0].K.apply(U);
    spread_forces(mesh_, move_.stencils()[0], as_points(f, 0, int(U.size() / 2)), force);
    flow_.diffusion().add_force_response(correction_, force);
  } else {  // −Δt Σ_p combination_p A⁻¹ S K z_p: the products' responses, added in order
    const std::size_t size = correction_.u1.size();
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < size; ++k) {
      double a = 0, b = 0;
      for (Eigen::Index p = 0; p < combination_.size(); ++p) {
        a += combination_[p] * responses_[p].u1[k];
        b += combination_[p] * responses_[p].u2[k];
      }
      correction_.u1[k] = -dt_ * a;
      correction_.u2[k] = -dt_ * b;
    }
  }
  cost_.correction += seconds_since(t0);
  return correction_;
}

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

void SemiImplicitMembraneStep::fit_turns(const std::vector<Cell>& cells) {
  // Each block's rotation onto its cell's nodes (the header). None unless turned blocks are asked
  // for and the blocks only precondition.
  turn_.clear();
  if (!options_.turn_blocks || !several_ || block_nodes_.size() != cells.size()) return;
  turn_.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) turn_[c] = best_fit_rotation(block_nodes_[c], cells[c].nodes);
}

void SemiImplicitMembraneStep::build_block(int c, const Points& r, double target_area, double kb_scale) {
  // The cell's own system I + Δt M_cc K_c at nodes r, factored once (K and M both at r); with
  // several cells M̄_cc, M averaged over the cell's phase on the grid along x1 (step_mobility.hpp).
  const MembraneStiffness K = membrane_stiffness(model_of(model_, kb_scale), r, target_area);
  Eigen::MatrixXd M;
  if (several_)
    mobility_.phase_averaged_matrix(r, M);  // a preconditioner that a cell carried along x1 keeps
  else
    mobility_.matrix(r, M);
  Eigen::MatrixXd B = dt_ * K.right_multiply(M);
  B.diagonal().array() += 1.0;
  if (several_)
  {
    const Eigen::PartialPivLU<Eigen::MatrixXf> lu(B.cast<float>());
    Block& b = blocks_[c];
    detail::pack_lu_bf16(lu.matrixLU().data(), int(B.rows()), b.lu_bf16);
    b.inverse_diagonal.resize(B.rows());
    for (Eigen::Index i = 0; i < B.rows(); ++i) b.inverse_diagonal[i] = 1.0f / lu.matrixLU()(i, i);
    // P B = L U with P = lu.permutationP(): row i of P B is row p⁻¹(i) of B.
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse = lu.permutationP().inverse();
    b.permutation.assign(inverse.indices().data(), inverse.indices().data() + B.rows());
  }
  else
    blocks_[c].lu.compute(B);
}

void SemiImplicitMembraneStep::save(CheckpointWriter& w) const {
  w.put(pressure_);
  w.put(last_U_);
  w.put(before_last_U_);
  w.put(last_rhs_);
  w.put(before_last_rhs_);
  w.put(std::int64_t(steps_since_rebuild_));
  w.put(std::int64_t(refresh_steps_));
  w.put(std::int64_t(rebuild_now_));
  w.put(std::int64_t(last_iterations_));
  w.put(std::int64_t(block_nodes_.size()));
  for (const Points& r : block_nodes_) w.put(r);
}

void SemiImplicitMembraneStep::load(CheckpointReader& r, const std::vector<Cell>& cells) {
  pressure_ = r.get_doubles(pressure_.size(), "the semi-implicit predictor's pressure");
  std::size_t unknowns = 0;
  for (const Cell& c : cells) unknowns += 2 * c.nodes.size();
  last_U_ = r.get_vector();
  before_last_U_ = r.get_vector();
  last_rhs_ = r.get_vector();
  before_last_rhs_ = r.get_vector();
  for (const Eigen::VectorXd* v : {&last_U_, &before_last_U_, &last_rhs_, &before_last_rhs_})
    if (v->size() != 0 && std::size_t(v->size()) != unknowns)
      throw CheckpointError(r.path() + ": the node velocities do not match the cells of this scene");
  steps_since_rebuild_ = int(r.get_int());
  refresh_steps_ = int(r.get_int());
  if (refresh_steps_ < 1 || refresh_steps_ > max_refresh_steps_)
    throw CheckpointError(r.path() + ": preconditioner refresh interval " + std::to_string(refresh_steps_) + " out of range [1, " +
                          std::to_string(max_refresh_steps_) + "]");
  rebuild_now_ = r.get_int() != 0;
  last_iterations_ = int(r.get_int());
  const std::int64_t nblocks = r.get_int();
  if (nblocks != 0 && nblocks != std::int64_t(cells.size()))
    throw CheckpointError(r.path() + ": preconditioner blocks for " + std::to_string(nblocks) + " cells, the scene has " +
                          std::to_string(cells.size()));
  block_nodes_.resize(std::size_t(nblocks));
  for (std::size_t c = 0; c < block_nodes_.size(); ++c)
    block_nodes_[c] = r.get_points(cells[c].nodes.size(), "the nodes of a preconditioner block");
  // The blocks as the uninterrupted run has them (built from the same nodes the same way).
  several_ = cells.size() > 1 || !x1_invariant_;
  if (several_ && !block_nodes_.empty()) mobility_.prepare_phase_average(phase_average_extent(model_));
  blocks_.resize(block_nodes_.size());
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < int(block_nodes_.size()); ++c) build_block(c, block_nodes_[c], cells[c].target_area, cells[c].kb_scale);
}

}  // namespace rbc
