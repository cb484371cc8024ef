#pragma once
// How membrane nodes move under forces on them through step 4 and the projection that follows
// (step 1 of the next step, whose velocity moves them in step 2): the mobility
//
//   U = M F,   M = J P A⁻¹ S   (2N × 2N for N nodes),
//
// with S, J the spreading and interpolation (10), (13) (weights φ_k(x) = h² D_h(x − r_k)), A step
// 4's Helmholtz operator (ρh²/Δt + 4μ) − μ(5-point sum) with zero velocity on the walls, and P the
// quasi-Stokes projection of step 1. F in N/m, U in m/s. P matters: without it a uniform normal
// force (the area penalty) would seem to change a cell's area freely, which an incompressible
// fluid forbids. The exact composition matters too: the discrete A and P do not commute (P lives
// on T_2h), and the symmetric J P A⁻¹ P S, which leaves out the part of the area force that
// P A⁻¹ does let through, made the coupling unstable (measured: a cell at rest, Δt = 1e-6 s).
// So M is not symmetric (its asymmetry is ≈ 20 % of its norm at h = 0.25 µm).
//
// P A⁻¹ is fixed for the run and invariant under shifts in x1 by two mesh cells (odd and even
// velocity columns sit differently on T_2h), so we tabulate it once:
// T_αβ(i' mod 2, i − i', j, j') = component α at node (i, j) of P A⁻¹ applied to a unit value in
// component β at node (i', j') — one source per column parity, interior row and component
// (4 (ny−1) fast solves and projections; 8 nx (ny−1)² values, 520 MB at 320 × 160). M of any set
// of nodes then costs 64 multiply-adds per pair and per (node, footprint node), see matrix().
// M equals the long way (spread, solve, P, interpolate) to the projection's tolerance — a test
// checks it.
#include <vector>

#include <Eigen/Dense>

#include "fluid/diffusion.hpp"
#include "fluid/quasi_stokes.hpp"
#include "membrane/spring_membrane.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

class StepMobility {
 public:
  StepMobility(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection, double rho, double dt);
  // M of the nodes r, 2N × 2N with unknowns (x_1, y_1, x_2, y_2, …), m/s per N/m.
  void matrix(const Points& r, Eigen::MatrixXd& M) const;
  std::size_t table_bytes() const { return table_.size() * sizeof(double); }

 private:
  // The 8 values (i' mod 2, α, β) at column offset di between rows j (response) and j' (source).
  double* entry(int j, int js, int di) { return &table_[((std::size_t(js) * rows_ + j) * m_.nx + di) * 8]; }
  const double* entry(int j, int js, int di) const { return &table_[((std::size_t(js) * rows_ + j) * m_.nx + di) * 8]; }
  ChannelMesh m_;
  int rows_;                   // interior rows ny − 1
  std::vector<double> table_;  // T at [((j' rows + j) nx + (i − i')) 8 + 4 (i' mod 2) + 2α + β]
};

}  // namespace rbc
