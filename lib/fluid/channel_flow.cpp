#include "fluid/channel_flow.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rbc {

double body_force_from_reynolds(double reynolds0, const FluidProperties& fluid, double height) {
  const double u0 = reynolds0 * fluid.viscosity / (fluid.density * height);
  return 12.0 * fluid.viscosity * u0 / (height * height);
}

double cell_free_peak_speed(const ChannelFlowParams& p) {
  return std::abs(p.body_force) * p.height * p.height / (8.0 * p.fluid.viscosity) +
         std::max(std::abs(p.wall_velocity[0]), std::abs(p.wall_velocity[1]));
}

double advective_dt_bound(const ChannelFlowParams& p) {
  const double u = cell_free_peak_speed(p);
  return u > 0 ? p.advection_substeps * kAdvectiveCfl * p.mesh_size / u : INFINITY;
}

ChannelFlow::ChannelFlow(const ChannelFlowParams& params)
    : p_(params),
      mesh_(ChannelMesh::make(params.length, params.height, params.mesh_size)),
      projection_(mesh_, params.preconditioner, params.cg_tolerance, params.cg_max_iterations),
      advection_(mesh_),
      diffusion_(mesh_, params.fluid.density, params.fluid.viscosity, implicit_dt()),
      u_(mesh_),
      pressure_(mesh_.pressure_nodes(), 0.0) {
  apply_wall_velocity();
}

void ChannelFlow::apply_wall_velocity() {
  for (int i = 0; i < mesh_.nx; ++i) {
    u_.u1[mesh_.v(i, 0)] = p_.wall_velocity[0];
    u_.u1[mesh_.v(i, mesh_.ny)] = p_.wall_velocity[1];
    u_.u2[mesh_.v(i, 0)] = u_.u2[mesh_.v(i, mesh_.ny)] = 0.0;
  }
}

void ChannelFlow::set_poiseuille() {
  // u1(x2) = f x2 (H − x2) / (2μ) + linear Couette part from the wall velocities.
  const double H = p_.height, f = p_.body_force, mu = p_.fluid.viscosity;
  for (int j = 0; j <= mesh_.ny; ++j) {
    const double y = mesh_.y(j);
    const double v = f * y * (H - y) / (2 * mu) + p_.wall_velocity[0] + (p_.wall_velocity[1] - p_.wall_velocity[0]) * y / H;
    for (int i = 0; i < mesh_.nx; ++i) { u_.u1[mesh_.v(i, j)] = v; u_.u2[mesh_.v(i, j)] = 0.0; }
  }
}

ProjectionReport ChannelFlow::project() {
  ProjectionReport r;
  if (!p_.incremental_pressure) {
    r = projection_.project(u_, u_, pressure_, p_.fluid.density, implicit_dt(), ProjectionForm::iterative);
  } else {
    // Incremental form: the projection's pressure is the increment φ (started from 0, its value in
    // a steady flow); p^{n+1} = p^n + φ.
    increment_.assign(pressure_.size(), 0.0);
    r = projection_.project(u_, u_, increment_, p_.fluid.density, implicit_dt(), ProjectionForm::iterative);
    for (std::size_t k = 0; k < pressure_.size(); ++k) pressure_[k] += increment_[k];
  }
  if (keep_stages_) kept_projected_ = u_;
  return r;
}

void ChannelFlow::advect() {
  const double dt = p_.dt;
  const int q = p_.advection_substeps;
  if (!p_.bdf2 || !history_) {
    advection_.advect(u_, u_, dt, q);
    if (keep_stages_) kept_advected_ = u_;
    return;
  }
  // The BDF2 scheme's step 3: the characteristics of [tⁿ, t^{n+1}] with the velocity at t^{n+1/2},
  // V = (3 P uⁿ − P u^{n−1})/2 (second order; divergence-free with both), carry P uⁿ to ûⁿ and
  // û^{n−1} (P u^{n−1} as the last step carried it to tⁿ) on to t^{n+1}; step 4 starts from
  // w = (4ûⁿ − û^{n−1})/3 (the study's wave-like method for each, with Q substeps).
  if (advecting_.u1.empty()) advecting_ = VelocityField(mesh_);
  for (std::size_t k = 0; k < u_.u1.size(); ++k) {
    advecting_.u1[k] = 1.5 * u_.u1[k] - 0.5 * previous_projected_.u1[k];
    advecting_.u2[k] = 1.5 * u_.u2[k] - 0.5 * previous_projected_.u2[k];
  }
  previous_projected_ = u_;                                   // P uⁿ, for the next step
  advection_.advect(advecting_, u_, dt, q);                   // ûⁿ
  advection_.advect(advecting_, previous_advected_, dt, q);   // û^{n−1}
  for (std::size_t k = 0; k < u_.u1.size(); ++k) {
    const double a1 = u_.u1[k], a2 = u_.u2[k];
    u_.u1[k] = (4.0 * a1 - previous_advected_.u1[k]) / 3.0;
    u_.u2[k] = (4.0 * a2 - previous_advected_.u2[k]) / 3.0;
    previous_advected_.u1[k] = a1;                            // ûⁿ, for the next step
    previous_advected_.u2[k] = a2;
  }
}

void ChannelFlow::diffuse(const VelocityField* force_field) {
  const double force[2] = {p_.body_force, 0.0};
  if (p_.incremental_pressure) {  // step 4 carries the pressure force M⁻¹ Bᵀ p^{n+1}
    if (step4_force_.u1.empty()) step4_force_ = VelocityField(mesh_);
    projection_.pressure_force(pressure_, step4_force_);
    if (force_field)
      for (std::size_t k = 0; k < step4_force_.u1.size(); ++k) {
        step4_force_.u1[k] += force_field->u1[k];
        step4_force_.u2[k] += force_field->u2[k];
      }
    force_field = &step4_force_;
  }
  diffusion_.diffuse(u_, force, force_field);
  t_ += p_.dt;
  ++steps_;
}

ProjectionReport ChannelFlow::step(const MembraneStep& membrane_step) {
  // The study's Lie scheme (its Section 2.4, eqs. (19)-(21) for the fluid):
  const ProjectionReport r = project();                                   // (1), eq. (19): u^{n+1/3}, p^{n+1}
  const VelocityField* f_B = membrane_step ? membrane_step() : nullptr;  // (2) membranes: r^{n+1}, f_B
  advect();                                                               // (3), eq. (20): u^{n+2/3}
  diffuse(f_B);                                                           // (4), eq. (21) with f_p + f_B: u^{n+1}
  return r;
}

void ChannelFlow::take_state(const ChannelFlow& from) {
  u_.u1 = from.u_.u1;
  u_.u2 = from.u_.u2;
  pressure_ = from.pressure_;
  t_ = from.t_;
}

void ChannelFlow::start_bdf2(const ChannelFlow& lie) {
  if (!p_.bdf2 || lie.p_.bdf2 || !lie.keep_stages_ || lie.steps_ != 1 || lie.p_.dt != p_.dt)
    throw std::logic_error("start_bdf2: needs a BDF2 flow and a Lie flow at the same dt after its first step, its stages kept");
  take_state(lie);
  steps_ = lie.steps_;
  previous_projected_ = lie.kept_projected_;
  previous_advected_ = lie.kept_advected_;
  history_ = true;
}

void ChannelFlow::save(CheckpointWriter& w) const {
  w.put(u_.u1);
  w.put(u_.u2);
  w.put(pressure_);
  w.put(t_);
  w.put(std::int64_t(steps_));
  if (p_.bdf2) {  // (only the BDF2 scheme: the other checkpoints stay as they were)
    w.put(std::int64_t(history_));
    if (history_)
      for (const VelocityField* f : {&previous_projected_, &previous_advected_}) {
        w.put(f->u1);
        w.put(f->u2);
      }
  }
}

void ChannelFlow::load(CheckpointReader& r) {
  u_.u1 = r.get_doubles(u_.u1.size(), "the velocity u1");
  u_.u2 = r.get_doubles(u_.u2.size(), "the velocity u2");
  pressure_ = r.get_doubles(pressure_.size(), "the pressure");
  t_ = r.get_double();
  steps_ = long(r.get_int());
  if (p_.bdf2) {
    history_ = r.get_int() != 0;
    if (history_ != (steps_ > 0))
      throw CheckpointError(r.path() + ": a BDF2 run's checkpoint after " + std::to_string(steps_) + " steps " +
                            (history_ ? "with" : "without") + " the scheme's history");
    if (history_)
      for (VelocityField* f : {&previous_projected_, &previous_advected_}) {
        *f = VelocityField(mesh_);
        f->u1 = r.get_doubles(f->u1.size(), "the BDF2 history's velocity u1");
        f->u2 = r.get_doubles(f->u2.size(), "the BDF2 history's velocity u2");
      }
  }
}

}  // namespace rbc
