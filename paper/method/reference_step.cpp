// One step of the study's Lie scheme, written out: the literate reference.
//
// Shi, Pan & Glowinski, "Numerical simulation of lateral migration of red blood cells in Poiseuille
// flows", Int. J. Numer. Meth. Fluids 68 (2012), DOI 10.1002/fld.2455, Section 2. The plasma obeys
//
//   ρ (∂u/∂t + u·∇u) = −∇p + μ Δu + f_p + f_B,   ∇·u = 0   in Ω = (0, L) × (0, H),          (1)-(2)
//
// periodic in x1, with no slip on the walls x2 = 0, H; f_p is the body force that drives the flow
// and f_B the force of the cell membranes on the fluid. The study splits one step tⁿ → tⁿ⁺¹ (its
// Lie scheme, Section 2.4) into four fractional steps, which this file takes in order:
//
//   (1) quasi-Stokes projection     uⁿ → u^{n+1/3}, p^{n+1}          (19)        01_fluid_steps.md
//   (2) membrane                    rⁿ → r^{n+1}, f_B^{n+1}          (13)-(14),  03_immersed_boundary.md
//                                                                     (8), (10)   02_membrane.md
//   (3) wave-like advection         u^{n+1/3} → u^{n+2/3}            (20)        01_fluid_steps.md
//   (4) diffusion with the forces   u^{n+2/3} → u^{n+1}              (21)        01_fluid_steps.md
//
// This is what Simulation::step (lib/scene/simulation.cpp) does for a channel with cells and the
// explicit coupling, without the speed: one scalar, serial sequence on the library's operators (the
// P1 matrices, the fast solvers, the discrete delta, the membrane force), each called once in plain
// view. tests/test_reference_step.cpp checks that the two take the same step to round-off over 100
// steps of paper/method/scenes/single_cell_coarse.toml (under a second). The walk-through,
// paper/method/README.md, starts here.
#include "reference_step.hpp"

#include <stdexcept>

#include <Eigen/Core>

#include "fem/p1_operators.hpp"
#include "immersed_boundary/immersed_boundary.hpp"
#include "membrane/shape_preparation.hpp"
#include "membrane/spring_membrane.hpp"

namespace rbc {

namespace {

// ---------------------------------------------------------------------------------------------
// Space: P1-iso-P2 on a uniform triangulation (the study's Section 2.4; chapter 01_fluid_steps.md).
//
// T_h is the grid of squares of side h, each cut by the same diagonal; the velocity is P1 on T_h,
// its nodes (i h, j h) with j = 0 and j = ny on the walls. The pressure is P1 on T_2h, whose
// midpoint refinement is T_h. On this mesh the finite-element matrices are stencils (lib/fem/):
//
//   M   the lumped mass, M_nn = ∫ φ_n = h² at an interior velocity node
//   K   the P1 stiffness, K_nm = ∫ ∇φ_n · ∇φ_m: the 5-point Laplacian inside
//   B   the divergence, (B u)_Q = ∫ q_Q ∇·u_h, one row per node Q of T_2h
//
// Every operator of the step commutes with the shift in x1, so the fast solver (an FFT in x1, then
// one banded LU per Fourier mode in x2; lib/fast_solvers/) inverts it exactly. Two are inverted:
// the pressure's S = B M⁻¹ Bᵀ in step 1 and the diffusion's A = (ρ/Δt) M + μ K in step 4.
// ---------------------------------------------------------------------------------------------

// S p = B M⁻¹ Bᵀ p on T_2h (Bᵀ p is zero on the wall rows, where the velocity is prescribed).
PeriodicBandedSolver::Operator schur_operator(const ChannelMesh& m, const DivergenceStencil& B) {
  const double inv_mass = 1.0 / (m.h * m.h);
  return [&B, inv_mass](const std::vector<double>& p, std::vector<double>& out) {
    std::vector<double> g1, g2;
    B.apply_transpose(p, g1, g2);
    for (std::size_t n = 0; n < g1.size(); ++n) {
      g1[n] *= inv_mass;
      g2[n] *= inv_mass;
    }
    B.apply(g1, g2, out);
  };
}

// ρh²/Δt (kg/(m s)): the lumped mass of an interior velocity node over the step, times ρ.
double mass_over_dt(const Scene& scene, const ChannelMesh& m) { return scene.fluid.density * (m.h * m.h) / scene.dt; }

// A u = a u + μ K u, a = ρh²/Δt, on the interior rows j = 1..ny−1 (x1 fastest), the wall rows held at
// zero: their values are known and step 4 moves them to the right-hand side.
PeriodicBandedSolver::Operator helmholtz_operator(const ChannelMesh& m, double a, double mu) {
  const SparseMatrix K = assemble_p1_stiffness(m.nx, m.ny);  // nx × (ny + 1) nodes, walls included
  return [m, K, a, mu](const std::vector<double>& in, std::vector<double>& out) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(Eigen::Index(m.velocity_nodes()));
    for (std::size_t k = 0; k < in.size(); ++k) x[Eigen::Index(m.nx + k)] = in[k];
    const Eigen::VectorXd Kx = K * x;
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = a * in[k] + mu * Kx[Eigen::Index(m.nx + k)];
  };
}

// The lumped weights of T_2h's nodes (1 inside, ½ on the wall rows), which define the pressure's mean.
std::vector<double> pressure_weights(const ChannelMesh& m) {
  std::vector<double> w(m.pressure_nodes());
  for (int J = 0; J < m.pny(); ++J)
    for (int I = 0; I < m.pnx(); ++I) w[m.p(I, J)] = (J == 0 || J == m.pny() - 1) ? 0.5 : 1.0;
  return w;
}

void remove_mean(std::vector<double>& p, const std::vector<double>& w) {
  double wp = 0, total = 0;
  for (std::size_t k = 0; k < p.size(); ++k) wp += w[k] * p[k];
  for (double v : w) total += v;
  const double mean = wp / total;
  for (double& v : p) v -= mean;
}

}  // namespace

ReferenceOperators::ReferenceOperators(const Scene& scene)
    : mesh(ChannelMesh::make(scene.length, scene.height, scene.mesh_size)),
      B(mesh),
      pressure_weight(pressure_weights(mesh)),
      schur(mesh.pnx(), mesh.pny(), schur_operator(mesh, B), true),  // kernel: the constant pressure
      helmholtz(mesh.nx, mesh.ny - 1, helmholtz_operator(mesh, mass_over_dt(scene, mesh), scene.fluid.viscosity), false),
      advection(mesh),
      membrane(scene.membrane_model()) {
  // The scenes the study's four steps cover as written below; the rest add to step 4 (obstacles,
  // disks), after it (the semi-implicit correction) or to step 2's force (the repulsion).
  if (!scene.obstacles.empty() || !scene.disks.empty() || scene.coupling != "explicit" || scene.repulsion_strength > 0 ||
      scene.pressure_preconditioner != "schur")
    throw std::invalid_argument(scene.source + ": the reference step covers cells with the explicit coupling and the exact pressure "
                                "solve only (no [[obstacle]], no [[disk]], no [repulsion], [solver] pressure_preconditioner = \"schur\")");
}

// The start (the study's eqs. (3)-(4), u(0) = 0, and its Remark 2.1): the fluid at rest, the walls at
// their velocity, p = 0, and each cell its prepared shape, the minimiser of E_l + E_b + E_s at the
// target area s* π R0², placed at its centre and angle.
ReferenceState reference_start(const Scene& scene, const ReferenceOperators& ops) {
  const ChannelMesh& m = ops.mesh;
  ReferenceState s;
  s.u = VelocityField(m);
  for (int i = 0; i < m.nx; ++i) {
    s.u.u1[m.v(i, 0)] = scene.wall_velocity[0];
    s.u.u1[m.v(i, m.ny)] = scene.wall_velocity[1];
  }
  s.p.assign(m.pressure_nodes(), 0.0);
  for (const CellSpec& c : scene.cells) {
    const PreparedShape shape = prepare_shape(model_of(ops.membrane, c.kb_scale), c.swelling_ratio);
    s.cells.push_back(make_cell(shape, c.swelling_ratio, c.center, c.angle, c.kb_scale));
  }
  return s;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Step (1): the quasi-Stokes projection, eq. (19) (chapter 01_fluid_steps.md, "Time: the Lie scheme").
//
//   find u^{n+1/3} ∈ W_0h, p ∈ L²_{h,0}:
//     ρ ∫ (u^{n+1/3} − uⁿ)/Δt · v − ∫ p ∇·v = 0   for all v ∈ W_0h,     ∫ q ∇·u^{n+1/3} = 0   for all q.
//
// In matrices, ρ M (u^{n+1/3} − uⁿ)/Δt = Bᵀ p and B u^{n+1/3} = 0. Eliminating u^{n+1/3} leaves the
// pressure's equation S p = −(ρ/Δt) B uⁿ with S = B M⁻¹ Bᵀ. The study solves it by conjugate
// gradients; the fast solver inverts S exactly, and CG's first iterate is then the solution (the
// library's default, [solver] pressure_preconditioner = "schur"; with "laplacian" its CG stops at
// [solver] cg_tolerance instead). S's kernel is the constant: we take p mean-zero. Then
// u^{n+1/3} = uⁿ + (Δt/ρ) M⁻¹ Bᵀ p.
//
// The pressure's form ([time] projection; chapter 01, "The pressure"): in the study's, p is p^{n+1}.
// In the incremental one (van Kan 1986) step 4 has carried the force of pⁿ, so p is the increment φ
// and p^{n+1} = pⁿ + φ.
// ---------------------------------------------------------------------------------------------
void quasi_stokes_step(ReferenceState& s, const Scene& scene, ReferenceOperators& ops) {
  const double rho = scene.fluid.density, dt = scene.dt, inv_mass = 1.0 / (ops.mesh.h * ops.mesh.h);
  // The right-hand side b = −(ρ/Δt) B uⁿ, one value per node of T_2h ...
  std::vector<double> b;
  ops.B.apply(s.u.u1, s.u.u2, b);
  for (double& v : b) v *= -rho / dt;
  // ... the pressure p = S⁻¹ b, mean-zero ...
  std::vector<double> p(b.size());
  ops.schur.solve(b.data(), p.data());
  remove_mean(p, ops.pressure_weight);
  // ... and the velocity it corrects, u^{n+1/3} = uⁿ + (Δt/ρ) M⁻¹ Bᵀ p on the interior nodes.
  ops.B.add_transpose(p, dt / rho * inv_mass, s.u.u1, s.u.u2, s.u.u1, s.u.u2);
  if (scene.projection == "incremental")
    for (std::size_t k = 0; k < p.size(); ++k) s.p[k] += p[k];
  else
    s.p = p;
}

// ---------------------------------------------------------------------------------------------
// Step (2): the membrane, with the study's explicit coupling (chapter 03_immersed_boundary.md for the
// transfers, 02_membrane.md for the force).
//
// The membrane lives on its own nodes r_i, the fluid on the mesh; Peskin's 4-point function φ
// builds the discrete delta δ_h(z) = φ(z/h)/h, D_h(x) = δ_h(x1) δ_h(x2) (11)-(12). We move every node
// with the fluid of step 1,
//
//   U(r_i) = Σ_x h² u^{n+1/3}(x) D_h(x − r_i),     r_i^{n+1} = r_iⁿ + Δt U(r_iⁿ),           (13)-(14)
//
// then take the spring forces where the nodes now are and spread them onto the mesh:
//
//   F_i = −∂(E_l + E_b + E_s)/∂r_i (r^{n+1}),     f_B^{n+1}(x) = Σ_i F_i D_h(x − r_i^{n+1}).   (8), (10)
//
// f_B is the force density (N/m³) step 4 diffuses; the part spread onto the wall rows is dropped,
// since the velocity there is prescribed.
// ---------------------------------------------------------------------------------------------
void membrane_step(ReferenceState& s, const Scene& scene, const ReferenceOperators& ops, VelocityField& f_B) {
  const ChannelMesh& m = ops.mesh;
  for (Cell& c : s.cells) {
    Points U;
    interpolate_velocity(m, s.u, c.nodes, U);  // (13)
    for (std::size_t i = 0; i < c.nodes.size(); ++i) c.nodes[i] += scene.dt * U[i];  // (14)
  }
  f_B = VelocityField(m);
  for (const Cell& c : s.cells) {
    Points F;
    membrane_energy(model_of(ops.membrane, c.kb_scale), c.nodes, c.target_area, &F);  // (8), with the cell's own k_b
    spread_forces(m, c.nodes, F, f_B);                                                // (10)
  }
}

// ---------------------------------------------------------------------------------------------
// Step (3): advection, eq. (20), by the wave-like equation method of Dean & Glowinski (chapter
// 01_fluid_steps.md).
//
//   ∂u/∂t + (V·∇)u = 0 on (tⁿ, tⁿ⁺¹),   u(tⁿ) = u^{n+1/3},   V = u^{n+1/3} frozen.
//
// Since ∇·V = 0, u also solves the wave-like equation ∂²u/∂t² − ∇·((V·∇u) V) = 0 with
// ∂u/∂t(tⁿ) = −(V·∇)u^{n+1/3}; its weak form with the lumped mass is M ü + A_V u = 0,
// (A_V)_nm = ∫ (V·∇φ_m)(V·∇φ_n). We take Q ([time] advection_substeps) explicit centred substeps of
// τ = Δt/Q, the first the Taylor step u¹ = u⁰ + τ u̇⁰ − (τ²/2) M⁻¹ A_V u⁰ with M u̇⁰ = −C_V u⁰,
// (C_V)_nm = ∫ (V·∇φ_m) φ_n. The result is u^{n+2/3}. (WaveLikeAdvection keeps A_V and C_V to
// itself, so the substeps are its one call.)
// ---------------------------------------------------------------------------------------------
void advection_step(ReferenceState& s, const Scene& scene, ReferenceOperators& ops) {
  ops.advection.advect(s.u, s.u, scene.dt, scene.advection_substeps);
}

// ---------------------------------------------------------------------------------------------
// Step (4): diffusion with the forces, eq. (21) (chapter 01_fluid_steps.md).
//
//   ρ ∫ (u^{n+1} − u^{n+2/3})/Δt · v + μ ∫ ∇u^{n+1} : ∇v = ∫ (f_p + f_B) · v   for all v ∈ W_0h,
//
// with u^{n+1} the wall velocity on the walls. With M and K this is, for each component on the
// interior nodes, one Helmholtz problem for the fast solver:
//
//   A u^{n+1} = (ρ/Δt) M u^{n+2/3} + M f + μ u_wall (on the rows next to the walls),   A = (ρ/Δt) M + μ K,
//
// i.e. (ρh²/Δt + 4μ) u_ij − μ (u_{i±1,j} + u_{i,j±1}) = (ρh²/Δt) u^{n+2/3}_ij + h² f_ij. In the
// incremental pressure form f also carries the pressure force of p^{n+1}, M⁻¹ Bᵀ p^{n+1} (= −∇p).
// ---------------------------------------------------------------------------------------------
void diffusion_step(ReferenceState& s, const Scene& scene, ReferenceOperators& ops, const VelocityField& f_B) {
  const ChannelMesh& m = ops.mesh;
  const int nx = m.nx, rows = m.ny - 1;
  const double h2 = m.h * m.h, inv_mass = 1.0 / h2, a = mass_over_dt(scene, m);
  const double mu = scene.fluid.viscosity, f_p[2] = {scene.driving_force(), 0.0};  // f_p in N/m³, along x1
  // The force density f: f_B, plus the pressure force M⁻¹ Bᵀ p^{n+1} in the incremental form (made
  // first and then added, rounded as the library rounds it: fused into one multiply-add it is an ulp
  // off, and the two runs of the test then end 1e-12 of the velocity apart after 100 steps).
  VelocityField f = f_B;
  if (scene.projection == "incremental") {
    VelocityField pressure_force;
    ops.B.apply_transpose(s.p, pressure_force.u1, pressure_force.u2);
    for (std::size_t n = 0; n < f.u1.size(); ++n) {
      pressure_force.u1[n] *= inv_mass;
      pressure_force.u2[n] *= inv_mass;
    }
    for (std::size_t n = 0; n < f.u1.size(); ++n) {
      f.u1[n] += pressure_force.u1[n];
      f.u2[n] += pressure_force.u2[n];
    }
  }
  // The right-hand sides of the two components, interior rows j = 1..ny−1, x1 fastest ...
  std::vector<double> rhs[2];
  for (int c = 0; c < 2; ++c) {
    const std::vector<double>& u = c == 0 ? s.u.u1 : s.u.u2;
    const std::vector<double>& fc = c == 0 ? f.u1 : f.u2;
    rhs[c].resize(std::size_t(nx) * rows);
    for (int j = 1; j <= rows; ++j)
      for (int i = 0; i < nx; ++i)
        rhs[c][std::size_t(j - 1) * nx + i] = a * u[m.v(i, j)] + h2 * (f_p[c] + fc[m.v(i, j)]);
    for (int i = 0; i < nx; ++i) {  // the known wall values, moved from K's rows to the right
      rhs[c][i] += mu * u[m.v(i, 0)];
      rhs[c][std::size_t(rows - 1) * nx + i] += mu * u[m.v(i, m.ny)];
    }
  }
  // ... u^{n+1} = A⁻¹ rhs, both components in one call; the wall rows keep their values.
  ops.helmholtz.solve_pair(rhs[0].data(), rhs[1].data(), rhs[0].data(), rhs[1].data());
  for (int j = 1; j <= rows; ++j)
    for (int i = 0; i < nx; ++i) {
      s.u.u1[m.v(i, j)] = rhs[0][std::size_t(j - 1) * nx + i];
      s.u.u2[m.v(i, j)] = rhs[1][std::size_t(j - 1) * nx + i];
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// One step tⁿ → tⁿ⁺¹ of the study's Lie scheme (Section 2.4): the four fractional steps in order.
// ---------------------------------------------------------------------------------------------
void reference_step(ReferenceState& s, const Scene& scene, ReferenceOperators& ops) {
  quasi_stokes_step(s, scene, ops);             // (1) eq. (19): u^{n+1/3}, p^{n+1}
  VelocityField f_B;
  membrane_step(s, scene, ops, f_B);            // (2) eqs. (13)-(14), (8), (10): r^{n+1}, f_B^{n+1}
  advection_step(s, scene, ops);                // (3) eq. (20): u^{n+2/3}
  diffusion_step(s, scene, ops, f_B);           // (4) eq. (21): u^{n+1}
  s.t += scene.dt;
  ++s.steps;
}

}  // namespace rbc
