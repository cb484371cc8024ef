#include "semi_implicit/semi_implicit_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "immersed_boundary/immersed_boundary.hpp"
#include "semi_implicit/detail/stopwatch.hpp"

namespace rbc {

SemiImplicitMembraneStep::SemiImplicitMembraneStep(ChannelFlow& flow, const MembraneModel& model, double tolerance,
                                                   const CouplingOptions& options)
    : flow_(flow),
      tolerance_(tolerance),
      mesh_(flow.mesh()),
      model_(model),
      dt_(flow.implicit_dt()),
      projected_(flow.mesh()),
      pressure_(flow.mesh().pressure_nodes(), 0.0),
      exact_pressure_(flow.mesh().pressure_nodes(), 0.0),
      move_(flow.mesh(), model),
      mobility_(flow.mesh(), flow.diffusion(), flow.projection(), flow.params().fluid.density, flow.implicit_dt()),
      correction_(flow.mesh()),
      preconditioner_(mobility_, model, flow.implicit_dt(), options.turn_blocks),
      options_(options),
      work_(flow.mesh()) {}

std::string describe(const CouplingOptions& o) {
  return std::string("start ") + (o.start == CouplingOptions::Start::kConstant ? "constant" : "linear") + ", blocks " +
         (o.turn_blocks ? "turned" : "fixed") + ", products " +
         (o.product_precision == CouplingProducts::Precision::kDouble ? "double" : "single where possible") + ", P at " +
         (o.projection == CouplingOptions::Projection::kSweep       ? "the mesh"
          : o.projection == CouplingOptions::Projection::kFootprint ? "the stencils"
                                                                    : "the stencils where cheaper");
}

void SemiImplicitMembraneStep::set_fluid_not_x1_invariant() {
  x1_invariant_ = false;
  products_.reset();  // chosen again for the constrained step 4
}

CouplingProducts& SemiImplicitMembraneStep::products() {
  // Made at first use: the fluid's step 4 (with or without a constraint) is then installed.
  if (!products_)
    products_ = std::make_unique<CouplingProducts>(mesh_, flow_.diffusion(), flow_.projection(), flow_.params().fluid.density, dt_,
                                                   options_.product_precision);
  return *products_;
}

Eigen::VectorXd SemiImplicitMembraneStep::apply_full(const std::vector<Cell>& cells, const Eigen::VectorXd& v) {
  // (I + Δt M K) v with M = J P A⁻¹ S over all cells at once, the long way (exact).
  detail::Stopwatch whole, part;
  ++cost_.product_count;
  const int ncells = int(cells.size());
  // h² S K v, spread straight into step 4's right-hand sides (weights φ_x φ_y: S has 1/h²).
  // K v first, every cell on its own (shared evenly by the threads), then the spreading
  // (detail/parallel_spreading.hpp: in parallel, each node's sum in a fixed order).
  kv_.resize(v.size());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < ncells; ++c) {
    const Eigen::Index n = offset_[c + 1] - offset_[c];
    kv_.segment(offset_[c], n) = stiffness_[c].apply(v.segment(offset_[c], n));
  }
  const std::pair<double*, double*> rhs = products().force_rhs();
  spreading_.run(ncells, std::size_t(mesh_.nx) * (mesh_.ny - 1), rhs.first, rhs.second, [&](int c, double* f1, double* f2) {
    spread_forces_interior(mesh_, move_.stencils()[c], kv_.data() + offset_[c], f1, f2);
  });
  part.lap(cost_.product_spread);
  // A⁻¹ S K v, kept for the correction (u^{n+1} − u⁰ is a combination of these), then P: over
  // the mesh, or at the footprint only (footprint_, see predict).
  if (int(responses_.size()) <= products_in_step_) responses_.emplace_back(mesh_);
  VelocityField& response = responses_[products_in_step_++];
  part.restart();  // (the field's first allocation counted in no part)
  products_->response(response);
  part.lap(cost_.product_solve);
  if (project_at_footprint_)
    project_at_footprint(response, products_->pressure(response));
  else
    products_->project(response, work_);
  part.lap(cost_.product_project);
  Eigen::VectorXd out = v;
#pragma omp parallel for schedule(static)
  for (int c = 0; c < ncells; ++c) {  // out += Δt J P A⁻¹ S K v
    thread_local Points U;
    interpolate_projected(c, work_, U);
    for (std::size_t k = 0; k < U.size(); ++k) {
      out[offset_[c] + 2 * k] += dt_ * U[k].x();
      out[offset_[c] + 2 * k + 1] += dt_ * U[k].y();
    }
  }
  whole.lap(cost_.products);
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
  // such errors, and at larger Δt the trend it follows is worth less than that. Measured at
  // Δt = 3e-6 s, 300 steps from the end of each cell_free_layer run, GMRES iterations per step,
  // linear → constant: 8.47 → 7.74 (50 cells, seed 1), 7.58 → 6.89 (seed 2), 10.95 → 10.00
  // (seed 3), 8.70 → 8.55, 8.47 → 8.15, 8.47 → 8.19 (100 cells, seeds 1–3), with 3–38 % fewer
  // block rebuilds. From rest in the developed profile, the cells still accelerating, the
  // straight line does better (100 cells: 4.1 against 6.2 products a step at 1.2e-6 s, 6.7
  // against 7.5 at 2e-6 s). CouplingOptions chooses the constant start: the study's long runs
  // spend nearly all their steps in the developed flow.
  const bool warm = last_U_.size() == rhs.size() && last_rhs_.size() == rhs.size();
  Eigen::VectorXd x0;
  if (warm && options_.start == Start::kLinear && before_last_U_.size() == rhs.size() && before_last_rhs_.size() == rhs.size())
    x0 = 2.0 * last_U_ - before_last_U_ + preconditioner_.apply(rhs - 2.0 * last_rhs_ + before_last_rhs_, offset_);
  else if (warm)
    x0 = last_U_ + preconditioner_.apply(rhs - last_rhs_, offset_);
  const double target = tolerance_ * rhs.norm();
  last_iterations_ = 0;
  bool converged = false;
  Eigen::VectorXd U = gmres(cells, rhs, x0, warm, fresh_blocks_after_, target, converged);
  if (!converged) {
    // The blocks have gone too stale for this Δt (the cells moved further than they were built
    // ahead for): rebuild them at the nodes of this step and go on from where GMRES got to.
    const detail::Stopwatch watch;
    preconditioner_.rebuild_fresh(cells, offset_);
    fresh_in_step_ = true;
    const double seconds = watch.seconds();  // counted as blocks, not as the coupled solve
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
    Z.col(k) = preconditioner_.apply(V.col(k), offset_);
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

// After step 4 with F^{n+1}: predict the nodes' velocities U⁰ = J P u⁰, solve the coupled system
// (I + Δt M K) U = U⁰, and return step 4's response to −Δt K U (the header's equations).
const VelocityField* SemiImplicitMembraneStep::implicit_correction(const std::vector<Cell>& cells, const VelocityField& u) {
  ++cost_.steps;
  detail::Stopwatch watch;
  const Eigen::VectorXd rhs = predict(cells, u);
  watch.lap(cost_.predictor);
  prepare_system(cells);
  watch.lap(cost_.blocks);
  const Eigen::VectorXd U = solve_system(cells, rhs);
  watch.lap(cost_.coupled);
  correct(U);
  watch.lap(cost_.correction);
  cost_.preconditioner = preconditioner_.apply_seconds();
  cost_.block_builds = preconditioner_.block_builds();
  cost_.fresh_rebuilds = preconditioner_.fresh_rebuilds();
  return &correction_;
}

Eigen::VectorXd SemiImplicitMembraneStep::predict(const std::vector<Cell>& cells, const VelocityField& u) {
  products_in_step_ = 0;
  const int ncells = int(cells.size());
  offset_.assign(ncells + 1, 0);
  for (int c = 0; c < ncells; ++c) offset_[c + 1] = offset_[c] + 2 * Eigen::Index(cells[c].nodes.size());
  // P u⁰: the velocity step 1 would hand to step 2 without the correction; U⁰ = J P u⁰ at the
  // nodes, unknowns (x_1, y_1, x_2, …). The nodes' stencils at r^{n+1}: step 2 made them to
  // spread F^{n+1}.
  const auto& stencils = move_.stencils();
  if (stencils.size() != cells.size()) throw std::logic_error("semi-implicit coupling: implicit_correction without step");
  // With the exact Schur preconditioner P is the products' projection, the exact form (CG takes
  // that one iteration too). J P needs P only under the stencils: where those nodes are few
  // against the mesh (a few cells) P is made there alone (QuasiStokesProjection::projected_at:
  // the sweep's values to round-off), its pressure still a solve over the mesh; a sweep over the
  // mesh fewer per product.
  const bool exact = flow_.projection().exact_schur_solve();
  project_at_footprint_ = false;
  if (exact && options_.projection != CouplingOptions::Projection::kSweep) {
    // kCheaper: the footprint while kFootprintNodeCost × its nodes < the mesh's nodes; a crowd's
    // build stops at that size (the sweep then) instead of walking every cell's stencils.
    const bool forced = options_.projection == CouplingOptions::Projection::kFootprint;
    project_at_footprint_ = footprint_.build(mesh_, stencils,
                                             forced ? std::numeric_limits<std::size_t>::max() : (mesh_.velocity_nodes() - 1) / kFootprintNodeCost);
  }
  // The exact form (without the exact solve: CG from p = 0), but for one cell with the Laplacian
  // preconditioner: CG from the last step's pressure.
  QuasiStokesProjection& P = flow_.projection();
  const double rho = flow_.params().fluid.density;
  if (project_at_footprint_) {
    P.pressure(u, exact_pressure_, rho, dt_, ProjectionForm::exact);
    project_at_footprint(u, exact_pressure_);
  } else if (exact || ncells > 1) {
    P.project(u, projected_, exact_pressure_, rho, dt_, ProjectionForm::exact);
  } else {
    P.project(u, projected_, pressure_, rho, dt_, ProjectionForm::iterative);
  }
  Eigen::VectorXd rhs(offset_[ncells]);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c) {
    Points U0;
    interpolate_projected(c, projected_, U0);
    rhs.segment(offset_[c], offset_[c + 1] - offset_[c]) = Eigen::Map<const Eigen::VectorXd>(U0[0].data(), 2 * U0.size());
  }
  spreading_.assign(mesh_, cells);
  return rhs;
}

void SemiImplicitMembraneStep::project_at_footprint(const VelocityField& u, const std::vector<double>& p) {
  // P u at the footprint's nodes (footprint1_, footprint2_).
  const auto& nodes = footprint_.nodes();
  footprint1_.resize(nodes.size());
  footprint2_.resize(nodes.size());
  const double rho = flow_.params().fluid.density;
#pragma omp parallel for schedule(static)
  for (std::size_t s = 0; s < nodes.size(); ++s)
    flow_.projection().projected_at(u, p, rho, dt_, nodes[s].first, nodes[s].second, footprint1_[s], footprint2_[s]);
}

void SemiImplicitMembraneStep::interpolate_projected(int c, const VelocityField& projected, Points& U) const {
  // J P at cell c's nodes: from the footprint's values, or from the projected field.
  if (project_at_footprint_)
    footprint_.interpolate(c, move_.stencils()[c], footprint1_.data(), footprint2_.data(), U);
  else
    interpolate_velocity(mesh_, projected, move_.stencils()[c], U);
}

void SemiImplicitMembraneStep::prepare_system(const std::vector<Cell>& cells) {
  // The cells' stiffness at r^{n+1} (the system's K), then the preconditioner's blocks for this
  // step (coupling_preconditioner.hpp: one cell's is its whole system).
  const int ncells = int(cells.size());
  several_ = ncells > 1 || !x1_invariant_;
  stiffness_.resize(ncells);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < ncells; ++c)
    stiffness_[c] = membrane_stiffness(model_of(model_, cells[c].kb_scale), cells[c].nodes, cells[c].target_area);
  preconditioner_.prepare(cells, stiffness_, several_, last_U_, offset_);
}

Eigen::VectorXd SemiImplicitMembraneStep::solve_system(const std::vector<Cell>& cells, const Eigen::VectorXd& rhs) {
  // One cell in an x1-invariant fluid: its own system is the whole system. Several, or a fluid
  // with obstacles or disks (the block, from the unobstructed mobility, is then only a
  // preconditioner): the coupled solve by GMRES.
  last_iterations_ = 0;
  fresh_in_step_ = false;
  const Eigen::VectorXd U = several_ ? solve_coupled(cells, rhs) : preconditioner_.apply(rhs, offset_);
  preconditioner_.after_solve(last_iterations_, fresh_in_step_);
  before_last_U_ = last_U_;
  last_U_ = U;
  before_last_rhs_ = last_rhs_;
  last_rhs_ = rhs;
  return U;
}

void SemiImplicitMembraneStep::correct(const Eigen::VectorXd& U) {
  // Step 4's response to ΔF = −Δt K U, the change of the spring force over the coming step.
  if (!several_) {  // spread ΔF and solve, as a product does (single precision where it may:
    // the products' few 1e-7 of the correction, against the correction of several cells, which
    // is a combination of such responses)
    const Eigen::VectorXd f = -dt_ * stiffness_[0].apply(U);
    auto [f1, f2] = products().force_rhs();
    spread_forces_interior(mesh_, move_.stencils()[0], f.data(), f1, f2);
    products().response(correction_);
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
}

void SemiImplicitMembraneStep::save(CheckpointWriter& w) const {
  w.put(pressure_);
  w.put(last_U_);
  w.put(before_last_U_);
  w.put(last_rhs_);
  w.put(before_last_rhs_);
  preconditioner_.save_schedule(w);
  w.put(std::int64_t(last_iterations_));
  preconditioner_.save_blocks(w);
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
  preconditioner_.load_schedule(r);
  last_iterations_ = int(r.get_int());
  several_ = cells.size() > 1 || !x1_invariant_;
  preconditioner_.load_blocks(r, cells, several_);
}

}  // namespace rbc
