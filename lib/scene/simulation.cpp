#include "scene/simulation.hpp"

#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "diagnostics/flow_diagnostics.hpp"
#include "membrane/membrane_crossing.hpp"
#include "membrane/membrane_stiffness.hpp"

namespace rbc {

Simulation::Simulation(const Scene& scene, const CouplingOptions& options)
    : scene_(scene), flow_(scene.flow_params()), model_(scene.membrane_model()), options_(options) {
  build_cells();
  // Obstacles: step 4 becomes the DLM/FD saddle-point problem (lib/fictitious_domain). Installed
  // after the semi-implicit coupling has tabulated its x1-invariant mobility, which then only
  // preconditions: the coupling's exact products go through the constrained step 4.
  if (!scene.obstacles.empty()) {
    obstacles_ = std::make_unique<ObstacleConstraint>(ObstacleGeometry(flow_.mesh(), scene.obstacles), flow_.diffusion().helmholtz(),
                                                      scene.obstacle_tolerance, parse_uzawa_preconditioner(scene.obstacle_preconditioner));
    flow_.diffusion().set_constraint(obstacles_.get());
    if (coupling_) coupling_->set_fluid_not_x1_invariant();
  }
  // Disks: step 4 holds each in rigid motion (lib/fictitious_domain/rigid_disks.hpp).
  if (!scene.disks.empty()) {
    for (const DiskSpec& d : scene.disks) {
      Disk disk;
      disk.center = d.center;
      disk.radius = d.radius;
      disks_.push_back(disk);
    }
    disk_constraint_ = std::make_unique<DiskConstraint>(flow_.mesh(), flow_.diffusion().helmholtz(), scene.fluid.density, scene.dt,
                                                        scene.disk_tolerance, DiskConstraint::kMaxIterations,
                                                        scene.disk_boundary_spacing);
    flow_.diffusion().set_constraint(disk_constraint_.get());
    if (coupling_) coupling_->set_fluid_not_x1_invariant();
  }
  // The BDF2 scheme: derived for the incremental form without obstacles or disks (the scene
  // reader refuses the others; so do we, for scenes built in code).
  if (scene.scheme == "bdf2" && (!flow_.params().incremental_pressure || obstacles_ || disk_constraint_))
    throw std::invalid_argument("Simulation: [time] scheme = \"bdf2\" needs projection = \"incremental\" and no obstacles or disks");
  // The extrapolated scheme's half steps: the same scene at Δt/2, Q kept (every part of the step
  // refined, the advection's substeps too), run by the study's scheme.
  if (scene.scheme == "lie-extrapolated") {
    Scene half = scene;
    half.scheme = "lie";
    half.extrapolate_pressure = true;  // (a choice of the extrapolated scheme, not of its half steps)
    half.dt = scene.dt / 2;
    half_step_ = std::make_unique<Simulation>(half, options);
  }
}

void Simulation::build_cells() {
  const Scene& scene = scene_;
  if (scene.cells.empty()) return;
  // Prepare each swelling ratio once (Remark 2.1) and place the cells.
  std::map<std::pair<double, double>, PreparedShape> shapes;  // by (s*, k_b scale): k_b/k_l enters the shape
  for (const CellSpec& c : scene.cells) {
    const std::pair<double, double> key{c.swelling_ratio, c.kb_scale};
    if (!shapes.count(key)) shapes.emplace(key, prepare_shape(model_of(model_, c.kb_scale), c.swelling_ratio));
    cells_.push_back(make_cell(shapes.at(key), c.swelling_ratio, c.center, c.angle, c.kb_scale));
  }
  if (scene.coupling == "semi-implicit")
    coupling_ = std::make_unique<SemiImplicitMembraneStep>(flow_, model_, scene.coupling_tolerance, options_);
  else
    coupling_ = std::make_unique<ExplicitMembraneStep>(flow_.mesh(), model_);
  // The scene's membrane repulsion (not in the study; off unless [repulsion] strength > 0).
  if (const MembraneRepulsion rep{scene.repulsion_range, scene.repulsion_strength}; rep.on())
    coupling_->membrane_move().set_repulsion(rep, scene.length, scene.height);
}

// One step tⁿ → tⁿ⁺¹: the study's Lie scheme L_Δt (lie_step), or with [time] scheme =
// "lie-extrapolated" its local Richardson extrapolation (paper/method/07_second_order_in_time.md),
//
//   Xⁿ⁺¹ = 2 L_{Δt/2}(L_{Δt/2}(Xⁿ)) − L_Δt(Xⁿ),   X = (u, p, membrane nodes, disks):
//
// the first-order error of L cancels, and its L-stable damping of stiff modes stays.
void Simulation::step() {
  if (scene_.scheme == "bdf2") {
    if (flow_.has_bdf2_history()) bdf2_step();
    else start_bdf2();
    return;
  }
  if (!half_step_) {
    lie_step();
    return;
  }
  half_step_->take_state(*this);  // Xⁿ
  try {
    half_step_->lie_step();
    half_step_->lie_step();       // L_{Δt/2}(L_{Δt/2}(Xⁿ))
  } catch (const RunFailure& e) {
    throw RunFailure(std::string(e.what()) + " (in the half steps of the extrapolated scheme, step " + std::to_string(steps() + 1) + ")");
  }
  lie_step();                     // L_Δt(Xⁿ)
  extrapolate_with(*half_step_);
  // A half step's pressure CG that stopped short stops the run as the step's own would (check_health).
  if (!half_step_->last_projection_.converged) last_projection_ = half_step_->last_projection_;
}

// The BDF2 scheme (paper/method/08_bdf2.md). Its fluid steps are ChannelFlow's in BDF2 form
// (ChannelFlowParams::bdf2); its step 2 moves the nodes by BDF2 with the velocity of tⁿ,
//
//   sⁿ = s̃^{n−1} + Δt' J(s_e) P uⁿ,   s̃^{n−1} = (4 s^{n−1} − s^{n−2})/3,   Δt' = 2Δt/3,
//
// J taken at s_e = 2 s^{n−1} − s^{n−2} (within O(Δt²) of sⁿ), and step 4 takes the force at the
// nodes' next positions s^{n+1} = s̃ⁿ + Δt' J P u^{n+1}, J, S and K at s_e = 2 sⁿ − s^{n−1}:
//
//   F(s^{n+1}) ≈ F(s_e) + K (s_e − s̃ⁿ) − Δt' K J P u^{n+1},
//
// the last term the semi-implicit coupling's (at Δt'); the explicit coupling takes F(s_e) alone.
// Step 4 receives the divergence-free part P f_B of the spread force: its gradient part, a
// pressure jump across each membrane that moves with it, would otherwise enter the pressure that
// the incremental form carries from step to step, and its splitting error with it (first order:
// the chapter's runs). That part's pressure, p_B, is the membranes' share of the pressure
// (pressure_with_membranes).
void Simulation::bdf2_step() {
  last_projection_ = flow_.step([this] { return bdf2_membrane_step(); });  // (1), (2), (3), (4) in BDF2 form
  if (coupling_) coupling_after_step4();
}

void Simulation::start_bdf2() {
  // The first step is the extrapolated Lie step (chapter 7), taken by the same scene in that
  // scheme from this state: its velocity, too, is within O(Δt²) of the flow's at t¹ (the Lie
  // step's is not: its step 4 takes the spring force where the nodes will be a step later, and
  // that first-order error, remembered by the fluid for about ρH²/μ, would leave the scheme first
  // order). It leaves s⁰ (the nodes now), s¹ (its nodes) and the fluid's history
  // (ChannelFlow::start_bdf2).
  Scene first = scene_;
  first.scheme = "lie-extrapolated";
  Simulation start(first, options_);
  start.take_state(*this);
  start.flow_.keep_stages();
  try {
    start.step();
  } catch (const RunFailure& e) {
    throw RunFailure(std::string(e.what()) + " (in the extrapolated Lie step that starts the BDF2 scheme)");
  }
  bdf_last_.resize(cells_.size());
  bdf_tilde_.resize(cells_.size());
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    bdf_last_[k] = cells_[k].nodes;
    bdf_tilde_[k] = cells_[k].nodes;  // (not read while the move is known: the next step finds it)
    cells_[k].nodes = start.cells_[k].nodes;
  }
  bdf_move_known_ = true;
  flow_.start_bdf2(start.flow_);
  last_projection_ = start.last_projection_;
  repulsion_steps_ += start.repulsion_steps_;
}

const VelocityField* Simulation::bdf2_membrane_step() {
  if (!coupling_) return nullptr;
  const ChannelMesh& mesh = flow_.mesh();
  const VelocityField& u = flow_.velocity();  // P uⁿ
  const double dt = flow_.implicit_dt();      // Δt'
  const bool implicit = scene_.coupling == "semi-implicit";
  const int n = int(cells_.size());
  bdf_extra_force_.resize(cells_.size());
#pragma omp parallel if (n > 1)
  {
    Points U, s;
#pragma omp for schedule(static)
    for (int k = 0; k < n; ++k) {
      Points& r = cells_[k].nodes;  // s_e, or s¹ after the start
      const std::size_t N = r.size();
      if (bdf_move_known_) {
        s = r;
      } else {
        interpolate_velocity(mesh, u, r, U);
        s.resize(N);
        for (std::size_t i = 0; i < N; ++i) s[i] = bdf_tilde_[k][i] + dt * U[i];  // sⁿ
      }
      Points& last = bdf_last_[k];
      Points& tilde = bdf_tilde_[k];
      tilde.resize(N);
      for (std::size_t i = 0; i < N; ++i) {
        tilde[i] = (4.0 * s[i] - last[i]) / 3.0;  // s̃ⁿ
        r[i] = 2.0 * s[i] - last[i];              // s_e
      }
      last = s;
      if (implicit) {  // K (s_e − s̃ⁿ) at s_e
        Eigen::VectorXd d(2 * N);
        for (std::size_t i = 0; i < N; ++i) d.segment<2>(2 * i) = r[i] - tilde[i];
        const Cell& c = cells_[k];
        const Eigen::VectorXd f = membrane_stiffness(model_of(model_, c.kb_scale), r, c.target_area).apply(d);
        bdf_extra_force_[k].resize(N);
        for (std::size_t i = 0; i < N; ++i) bdf_extra_force_[k][i] = f.segment<2>(2 * i);
      }
    }
  }
  bdf_move_known_ = false;
  ExplicitMembraneStep& spread = coupling_->membrane_move();
  const VelocityField& f_B = spread.spread(cells_, implicit ? &bdf_extra_force_ : nullptr);
  count_repulsion();
  // P f_B = f_B − ∇p_B (the projection's exact form with Δt/ρ = 1 s·m³/kg: p_B in Pa).
  if (bdf_force_.u1.empty()) bdf_force_ = VelocityField(mesh);
  bdf_force_pressure_.assign(mesh.pressure_nodes(), 0.0);
  flow_.projection().project(f_B, bdf_force_, bdf_force_pressure_, 1.0, 1.0, ProjectionForm::exact);
  return &bdf_force_;
}

std::vector<double> Simulation::pressure_with_membranes() const {
  std::vector<double> p = flow_.pressure();
  if (bdf_force_pressure_.size() == p.size())
    for (std::size_t k = 0; k < p.size(); ++k) p[k] += bdf_force_pressure_[k];
  return p;
}

void Simulation::take_state(const Simulation& from) {
  flow_.take_state(from.flow_);
  for (std::size_t k = 0; k < cells_.size(); ++k) cells_[k].nodes = from.cells_[k].nodes;
  disks_ = from.disks_;
}

void Simulation::extrapolate_with(const Simulation& finer) {
  // Richardson's first-order extrapolation from Δt and Δt/2: X ← 2 X_{Δt/2} − X_Δt, value by value
  // (the walls' velocities: 2 w − w = w; x1 unwrapped in both runs: no seam between them).
  auto richardson = [](auto& coarse, const auto& fine) { coarse = 2.0 * fine - coarse; };
  auto each = [&](auto& coarse, const auto& fine) {
    for (std::size_t k = 0; k < coarse.size(); ++k) richardson(coarse[k], fine[k]);
  };
  each(flow_.velocity().u1, finer.flow_.velocity().u1);
  each(flow_.velocity().u2, finer.flow_.velocity().u2);
  if (scene_.extrapolate_pressure)
    each(flow_.pressure(), finer.flow_.pressure());
  else  // the half steps' (Scene::extrapolate_pressure)
    flow_.pressure() = finer.flow_.pressure();
  for (std::size_t k = 0; k < cells_.size(); ++k) each(cells_[k].nodes, finer.cells_[k].nodes);
  for (std::size_t d = 0; d < disks_.size(); ++d) {
    const Disk& f = finer.disks_[d];
    richardson(disks_[d].center, f.center);
    richardson(disks_[d].velocity, f.velocity);
    richardson(disks_[d].angle, f.angle);
    richardson(disks_[d].angular_velocity, f.angular_velocity);
  }
}

// One step of the study's Lie scheme (the study's Section 2.4: its steps 1-4, its eqs. (19)-(21)
// for the fluid and (8), (10), (13)-(14) for the membranes), tⁿ → tⁿ⁺¹. The fluid's steps are
// ChannelFlow::step's, with the membranes' step 2 between its steps 1 and 3. The disks, where a
// scene has them, are held by step 4 and moved after it; the semi-implicit coupling adds its
// correction to step 4.
void Simulation::lie_step() {
  if (disk_constraint_) hold_disks_where_they_will_be();
  // (1) eq. (19), (3) eq. (20), (4) eq. (21); between (1) and (3) the membranes' step
  // (2), eqs. (8), (10), (13)-(14): r^{n+1}, f_B.
  last_projection_ = flow_.step([this] { return membrane_step(); });
  if (coupling_) coupling_after_step4();  // cells: the semi-implicit coupling's spring force at r^{n+2}
  if (disk_constraint_) move_disks();     // disks: G^{n+1}, θ^{n+1} from u^{n+1}
}

void Simulation::hold_disks_where_they_will_be() {
  // Step 4 holds the disks where they will be, G* = Gⁿ + Δt Vⁿ (GPHJ's prediction). Holding them
  // at Gⁿ lags the rigid field by one step, and the advected fluid inside a spinning, moving disk
  // then pushes it sideways at ω V Δt (tests/test_rigid_disks.cpp).
  std::vector<Disk> predicted = disks_;
  for (Disk& d : predicted) d.center += scene_.dt * d.velocity;
  disk_constraint_->set_disks(predicted);
}

const VelocityField* Simulation::membrane_step() {
  // Move the nodes with u^{n+1/3} and spread their forces F(r^{n+1}), in either coupling; step 4
  // adds the disks' contact forces over their area (none without disks; they depend on the disks'
  // places alone, which step 3 does not change).
  const VelocityField* f_B = nullptr;
  if (coupling_) {  // (the scene has cells)
    f_B = &coupling_->step(cells_, flow_.velocity(), scene_.dt);
    count_repulsion();
  }
  return disk_constraint_ ? add_contact_forces(f_B) : f_B;
}

void Simulation::count_repulsion() {
  if (scene_.repulsion_strength <= 0) return;  // count the steps in which the repulsion acted
  const RepulsionCount& c = coupling_->membrane_move().last_repulsion();
  if (c.wall_nodes + c.node_pairs > 0) ++repulsion_steps_;
}

void Simulation::coupling_after_step4() {
  // The semi-implicit coupling: u^{n+1} += step 4's response to −S Δt K U^{n+1}
  // (semi_implicit/semi_implicit_coupling.hpp); the study's explicit coupling adds nothing.
  try {
    if (const VelocityField* du = coupling_->implicit_correction(cells_, flow_.velocity())) flow_.add_velocity(*du);
  } catch (const std::runtime_error& e) {  // the coupled GMRES did not converge
    std::ostringstream m;
    m << e.what() << " at t = " << time() << " s (step " << steps() << "); lower [time] dt";
    throw RunFailure(m.str());
  }
}

void Simulation::move_disks() {
  // Their rigid motion in u^{n+1}; G^{n+1} = Gⁿ + Δt (Vⁿ + V^{n+1})/2, θ likewise.
  const std::vector<Eigen::Vector3d> q = disk_constraint_->rigid_motion(flow_.velocity());
  for (std::size_t k = 0; k < disks_.size(); ++k) {
    Disk& d = disks_[k];
    d.center += 0.5 * scene_.dt * (d.velocity + q[k].head<2>());
    d.angle += 0.5 * scene_.dt * (d.angular_velocity + q[k][2]);
    d.velocity = q[k].head<2>();
    d.angular_velocity = q[k][2];
  }
}

void Simulation::check_health() {
  const VelocityField& u = flow_.velocity();
  std::ostringstream s;
  s << " at t = " << time() << " s (step " << steps() << ")";
  const std::string when = s.str();
  if (!all_finite(u)) throw RunFailure("non-finite velocity" + when);
  if (!last_projection_.converged) {
    std::ostringstream m;
    m << "the pressure CG of step 1 stopped at relative residual " << last_projection_.residual << " after " << last_projection_.iterations
      << " iterations, above its tolerance " << flow_.params().cg_tolerance << when
      << ": its pressure is not the step's; use [solver] pressure_preconditioner = \"schur\" (exact) or a larger cg_tolerance";
    throw RunFailure(m.str());
  }
  check_disks(when);
  const ChannelFlowParams& p = flow_.params();
  const double speed = max_speed(u);
  const double cfl = speed * p.dt / (p.advection_substeps * p.mesh_size);
  if (cfl > 1.0) {
    std::ostringstream m;
    m << "CFL: the advective CFL number " << cfl << " exceeds the wave-like step's stability limit 1" << when;
    if (cells_.empty()) m << "; lower dt or raise [time] advection_substeps";
    else m << "; with cells this usually means the " << scene_.coupling << " membrane coupling went unstable: lower [time] dt";
    throw RunFailure(m.str());
  }
  // A saturated membrane oscillation (see kMaxSpeedRatio): the fluid faster than the flow's own
  // scale for longer than a start-up pulse lasts, or far faster at once (kBurstSpeedRatio).
  // Scenes without a driving flow have no scale.
  if (const double scale = cell_free_peak_speed(p); !cells_.empty() && scale > 0 && speed > kMaxSpeedRatio * scale) {
    speed_excess_time_ += p.dt;
    const double viscous_time = p.fluid.density * p.mesh_size * p.mesh_size / p.fluid.viscosity;  // ρh²/μ, s
    const bool burst = speed > kBurstSpeedRatio * scale;
    if (burst || speed_excess_time_ > kSpeedExcessViscousTimes * viscous_time) {
      std::ostringstream m;
      m << "membrane oscillation: the fluid reaches " << speed << " m/s";
      if (burst)
        m << ", more than " << kBurstSpeedRatio << " times the flow's own peak speed " << scale << " m/s";
      else
        m << " and has been faster than " << kMaxSpeedRatio << " times the flow's own peak speed " << scale << " m/s for "
          << speed_excess_time_ << " s in all (more than " << kSpeedExcessViscousTimes << " viscous times rho h^2/mu = "
          << viscous_time << " s)";
      m << when << ": the " << scene_.coupling << " coupling is unstable at this dt; lower [time] dt";
      throw RunFailure(m.str());
    }
  }
  const double l0 = model_.rest_length();
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    const std::string cell = "cell " + std::to_string(k);
    for (const auto& r : cells_[k].nodes) {
      if (!std::isfinite(r.x()) || !std::isfinite(r.y())) throw RunFailure("non-finite membrane node in " + cell + when);
      if (r.y() <= 0.0 || r.y() >= scene_.height)
        throw RunFailure(cell + " crossed a wall (a membrane node at x2 = " + std::to_string(r.y() * 1e6) + " um)" + when);
      if (obstacles_ && obstacles_->geometry().contains(r.x(), r.y()))
        throw RunFailure(cell + " entered an obstacle (a membrane node at (" + std::to_string(r.x() * 1e6) + ", " +
                         std::to_string(r.y() * 1e6) + ") um)" + when + "; lower [time] dt");
    }
    for (std::size_t d = 0; d < disks_.size(); ++d)
      for (const auto& r : cells_[k].nodes) {
        Eigen::Vector2d o = r - disks_[d].center;
        o.x() = nearest_image(o.x(), scene_.length);
        if (o.norm() < disks_[d].radius)
          throw RunFailure(cell + " entered disk " + std::to_string(d) + " (a membrane node " + std::to_string(o.norm() * 1e6) +
                           " um from its centre, radius " + std::to_string(disks_[d].radius * 1e6) + " um)" + when + "; lower [time] dt");
      }
    const double strain = max_strain(cells_[k].nodes, l0);
    if (strain > kMaxMembraneStrain) {
      std::ostringstream m;
      m << "membrane strain " << strain << " in " << cell << " exceeds " << kMaxMembraneStrain << when
        << ": the " << scene_.coupling << " coupling is unstable at this dt; lower [time] dt";
      throw RunFailure(m.str());
    }
  }
  // Two membranes crossing each other, or one itself (membrane_crossing.hpp): the cells
  // interpenetrate, or a membrane folded over.
  if (const auto c = find_membrane_crossing(cells_, scene_.length)) {
    std::ostringstream m;
    if (c->cell_a == c->cell_b)
      m << "membrane crossing: cell " << c->cell_a << " crosses itself (its segments " << c->segment_a << " and " << c->segment_b;
    else
      m << "membrane crossing: cells " << c->cell_a << " and " << c->cell_b << " cross each other (segment " << c->segment_a << " of cell "
        << c->cell_a << " and segment " << c->segment_b << " of cell " << c->cell_b;
    m << " at (" << c->point.x() * 1e6 << ", " << c->point.y() * 1e6 << ") um)" << when << "; lower [time] dt";
    throw RunFailure(m.str());
  }
}

std::vector<Eigen::Vector2d> Simulation::contact_forces() const {
  const double range = scene_.contact_range > 0 ? scene_.contact_range : 2 * scene_.mesh_size, L = scene_.length;
  std::vector<Eigen::Vector2d> F(disks_.size(), Eigen::Vector2d::Zero());
  auto push = [&](double gap) { return gap < range ? scene_.contact_strength * (range - gap) * (range - gap) / (range * range) : 0.0; };
  for (std::size_t a = 0; a < disks_.size(); ++a) {
    const Disk& d = disks_[a];
    F[a].y() += push(d.center.y() - d.radius) - push(scene_.height - d.center.y() - d.radius);  // the walls
    for (std::size_t b = a + 1; b < disks_.size(); ++b) {
      Eigen::Vector2d o = d.center - disks_[b].center;
      o.x() = nearest_image(o.x(), L);
      const double dist = o.norm(), f = push(dist - d.radius - disks_[b].radius);
      if (f > 0) {
        F[a] += f * o / dist;
        F[b] -= f * o / dist;
      }
    }
  }
  return F;
}

const VelocityField* Simulation::add_contact_forces(const VelocityField* f_B) {
  const std::vector<Eigen::Vector2d> F = contact_forces();
  bool any = false;
  for (const auto& f : F) any = any || f.squaredNorm() > 0;
  if (!any) return f_B;
  ++contact_steps_;
  // A uniform force density over each disk's nodes, F / (h² × their number): exactly F in all.
  const ChannelMesh& m = flow_.mesh();
  if (contact_field_.u1.size() != m.velocity_nodes()) contact_field_ = VelocityField(m);
  if (f_B) contact_field_ = *f_B;
  else {
    std::fill(contact_field_.u1.begin(), contact_field_.u1.end(), 0.0);
    std::fill(contact_field_.u2.begin(), contact_field_.u2.end(), 0.0);
  }
  const double h2 = m.h * m.h;
  for (std::size_t k = 0; k < disks_.size(); ++k) {
    const DiskPoints& p = disk_constraint_->points()[k];
    const Eigen::Vector2d f = F[k] / (h2 * p.interior_nodes);
    for (const auto* set : {&p.ring, &p.deep})
      for (const auto& pt : *set)
        if (pt.count == 1) {
          contact_field_.u1[std::size_t(m.nx) + std::size_t(pt.nodes[0])] += f.x();
          contact_field_.u2[std::size_t(m.nx) + std::size_t(pt.nodes[0])] += f.y();
        }
  }
  return &contact_field_;
}

void Simulation::check_disks(const std::string& when) const {
  for (std::size_t d = 0; d < disks_.size(); ++d) {
    const Disk& k = disks_[d];
    if (!std::isfinite(k.center.x()) || !std::isfinite(k.center.y()) || !std::isfinite(k.angular_velocity))
      throw RunFailure("non-finite position or spin of disk " + std::to_string(d) + when);
    if (k.center.y() - k.radius < scene_.mesh_size || k.center.y() + k.radius > scene_.height - scene_.mesh_size)
      throw RunFailure("disk " + std::to_string(d) + " came within one mesh cell of a wall (centre at x2 = " + std::to_string(k.center.y() * 1e6) +
                       " um)" + when + "; the contact force ([contact]) did not keep it off: raise its strength or lower [time] dt");
    for (std::size_t e = d + 1; e < disks_.size(); ++e) {
      Eigen::Vector2d o = disks_[e].center - k.center;
      o.x() = nearest_image(o.x(), scene_.length);
      if (o.norm() < k.radius + disks_[e].radius + scene_.mesh_size)
        throw RunFailure("disks " + std::to_string(d) + " and " + std::to_string(e) + " came within one mesh cell of each other" + when +
                         "; the contact force ([contact]) did not keep them apart: raise its strength or lower [time] dt");
    }
  }
}

void Simulation::save(CheckpointWriter& w) const {
  flow_.save(w);
  w.put(std::int64_t(last_projection_.iterations));
  w.put(last_projection_.residual);
  w.put(std::int64_t(cells_.size()));
  for (const Cell& c : cells_) w.put(c.nodes);
  w.put(speed_excess_time_);
  if (coupling_) coupling_->save(w);
  if (!disks_.empty()) {  // (nothing for scenes without disks: their checkpoints stay as they were)
    w.put(std::int64_t(disks_.size()));
    for (const Disk& d : disks_) w.put(Points{d.center, d.velocity, Eigen::Vector2d(d.angular_velocity, d.angle)});
    w.put(std::int64_t(contact_steps_));
  }
  if (scene_.repulsion_strength > 0) w.put(std::int64_t(repulsion_steps_));  // (only scenes with the repulsion)
  if (half_step_) half_step_->save(w);  // its solvers' warm starts (only the extrapolated scheme)
  if (scene_.scheme == "bdf2") {         // the nodes' history (empty before the first step)
    w.put(std::int64_t(bdf_move_known_));
    w.put(std::int64_t(bdf_last_.size()));
    for (std::size_t k = 0; k < bdf_last_.size(); ++k) {
      w.put(bdf_last_[k]);
      w.put(bdf_tilde_[k]);
    }
  }
}

void Simulation::load(CheckpointReader& r) {
  flow_.load(r);
  last_projection_.iterations = int(r.get_int());
  last_projection_.residual = r.get_double();
  const std::int64_t n = r.get_int();
  if (n != std::int64_t(cells_.size()))
    throw CheckpointError(r.path() + ": holds " + std::to_string(n) + " cells, the scene has " + std::to_string(cells_.size()));
  for (Cell& c : cells_) c.nodes = r.get_points(c.nodes.size(), "the membrane nodes of a cell");
  speed_excess_time_ = r.get_double();
  if (!(speed_excess_time_ >= 0) || speed_excess_time_ > time() + scene_.dt)  // at most the time run
    throw CheckpointError(r.path() + ": time spent above the speed limit " + std::to_string(speed_excess_time_) +
                          " s out of range [0, " + std::to_string(time()) + "] s (the time of the run)");
  if (coupling_) coupling_->load(r, cells_);
  if (!disks_.empty()) {
    const std::int64_t n = r.get_int();
    if (n != std::int64_t(disks_.size()))
      throw CheckpointError(r.path() + ": holds " + std::to_string(n) + " disks, the scene has " + std::to_string(disks_.size()));
    for (Disk& d : disks_) {
      const Points v = r.get_points(3, "the state of a disk");
      d.center = v[0];
      d.velocity = v[1];
      d.angular_velocity = v[2].x();
      d.angle = v[2].y();
    }
    contact_steps_ = long(r.get_int());
    if (contact_steps_ < 0 || contact_steps_ > steps())
      throw CheckpointError(r.path() + ": steps with a contact force " + std::to_string(contact_steps_) + " out of range [0, " +
                            std::to_string(steps()) + "]");
  }
  if (scene_.repulsion_strength > 0) {
    repulsion_steps_ = long(r.get_int());
    if (repulsion_steps_ < 0 || repulsion_steps_ > steps())
      throw CheckpointError(r.path() + ": steps with the membrane repulsion " + std::to_string(repulsion_steps_) + " out of range [0, " +
                            std::to_string(steps()) + "]");
  }
  if (half_step_) half_step_->load(r);
  if (scene_.scheme == "bdf2") {
    bdf_move_known_ = r.get_int() != 0;
    if (bdf_move_known_ != (steps() == 1))
      throw CheckpointError(r.path() + ": a BDF2 run's checkpoint after " + std::to_string(steps()) + " steps whose nodes' history " +
                            (bdf_move_known_ ? "is the start's" : "is not the start's"));
    const std::int64_t m = r.get_int();
    if (m != (steps() > 0 ? std::int64_t(cells_.size()) : 0))
      throw CheckpointError(r.path() + ": holds the BDF2 history of " + std::to_string(m) + " cells after " + std::to_string(steps()) +
                            " steps; the scene has " + std::to_string(cells_.size()) + " cells");
    bdf_last_.resize(std::size_t(m));
    bdf_tilde_.resize(std::size_t(m));
    for (std::size_t k = 0; k < bdf_last_.size(); ++k) {
      bdf_last_[k] = r.get_points(cells_[k].nodes.size(), "the BDF2 history of a cell");
      bdf_tilde_[k] = r.get_points(cells_[k].nodes.size(), "the BDF2 history of a cell");
    }
  }
}

void Simulation::place_cell(std::size_t k, const Points& nodes) {
  if (k >= cells_.size() || nodes.size() != cells_[k].nodes.size() || steps() > 0)
    throw std::invalid_argument("place_cell: no such cell, another node count, or the run has begun");
  cells_[k].nodes = nodes;
  cells_[k].prepared_area = enclosed_area(nodes);
  cells_[k].prepared_perimeter = perimeter(nodes);
}

}  // namespace rbc
