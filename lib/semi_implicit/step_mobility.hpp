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
// velocity columns sit differently on T_2h), so we tabulate it:
// T_αβ(i' mod 2, i − i', j, j') = component α at node (i, j) of P A⁻¹ applied to a unit value in
// component β at node (i', j') — one source per column parity, interior row and component
// (per source row j': 2 fast solves, one per column parity, the same for either component, and
// 4 projections; 8 nx (ny−1) values a row, 3.3 MB at
// 320 × 160, 520 MB for all 159 rows). A source row is tabulated when first needed: matrix()
// builds the rows under its nodes' stencils, so a run with one cell builds the rows its cell
// visits (about 25 of the wide channel's 159 at first); the phase average below needs every row.
// A row's values do not depend on when it is built. M of any set of nodes then costs 64
// multiply-adds per pair and per (node, footprint node), see matrix(). M equals the long way
// (spread, solve, P, interpolate) to the projection's tolerance — a test checks it.
//
// Several cells' preconditioner blocks (semi_implicit_coupling.hpp) use M averaged over a shift
// of all nodes together along x1, M̄(r) = (1/2h) ∫_0^{2h} M(r + s e1) ds. The grid-scale part of
// M depends on where the nodes sit between mesh lines, and a cell carried by the flow crosses
// them every few steps, so blocks built from M go stale as the cell moves; M̄ does not depend on
// that phase (a cell carried along x1 keeps its M̄). With the x1 weights φ(i − x/h) and
// T̄ = ½ Σ_{parity} T, the integral over s turns the two x1 weight sums into one kernel:
//
//   M̄_kl = Σ_{p,q} φ_y,k[p] φ_y,l[q] H(j_k + p, j_l + q, (x_k − x_l)/h),
//   H(j, j', z) = Σ_d c(d − z) T̄(d, j, j'),   c(z) = ∫ φ(τ) φ(τ + z) dτ,
//
// where c is the autocorrelation of Peskin's φ (support |z| < 4, Σ_d c(d − z) = 1). H is
// tabulated once (prepare_phase_average) for the row and x1 distances within one cell, at h/4
// in z, and read with linear interpolation (5.8e-4 of M̄ against the mean of M over 64 shifts,
// 1.5e-4 at h/8 with twice the table; the blocks are only a preconditioner, in single precision).
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "fluid/diffusion.hpp"
#include "fluid/quasi_stokes.hpp"
#include "membrane/spring_membrane.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

// The distance within which the phase-averaged blocks read H from its table: 0.6 of a cell's
// rest perimeter (two nodes of a cell are at most half the perimeter apart; 20 % for stretching).
inline double phase_average_extent(const MembraneModel& m) { return 0.6 * m.nodes * m.rest_length(); }

// c(z) = ∫ φ(τ) φ(τ + z) dτ for Peskin's 4-point φ (peskin_delta.hpp); zero for |z| ≥ 4.
double peskin_autocorrelation(double z);

class StepMobility {
 public:
  StepMobility(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection, double rho, double dt);
  // M of the nodes r, 2N × 2N with unknowns (x_1, y_1, x_2, y_2, …), m/s per N/m. Tabulates
  // the source rows under the nodes' stencils that are not yet (serially, before its threads).
  void matrix(const Points& r, Eigen::MatrixXd& M);
  // Source rows of T tabulated so far (of ny − 1), and their bytes.
  int rows_tabulated() const;
  std::size_t table_bytes() const;
  // Tabulates H for nodes at most extent (m) apart in x1 and in x2 (pairs further apart are
  // computed from T directly, slowly), with every source row of T. Idempotent for the same extent.
  void prepare_phase_average(double extent);
  // M̄ of the nodes r (see above), 2N × 2N, m/s per N/m. Needs prepare_phase_average.
  void phase_averaged_matrix(const Points& r, Eigen::MatrixXd& M) const;
  // Bytes of H for a mesh and extent (for the scene's memory check, before anything is built).
  static std::size_t phase_average_bytes(const ChannelMesh& mesh, double extent);
  static constexpr int kPhaseSamples = 4;  // samples of H per h in z

 private:
  // The 8 values (i' mod 2, α, β) at column offset di between rows j (response) and j' (source),
  // source row j' tabulated.
  double* entry(int j, int js, int di) { return &table_[js][offset(j, di)]; }
  const double* entry(int j, int js, int di) const { return &table_[js][offset(j, di)]; }
  std::size_t offset(int j, int di) const { return (std::size_t(j) * m_.nx + di) * 8; }  // in a source row's table
  // T for the sources in interior row js (2 fast solves, 4 projections), if not yet.
  void tabulate_source_row(int js);
  ChannelMesh m_;
  ImplicitDiffusion& diffusion_;
  QuasiStokesProjection& projection_;
  double rho_, dt_;
  int rows_;  // interior rows ny − 1
  // T of source row j' at table_[j'][(j nx + (i − i')) 8 + 4 (i' mod 2) + 2α + β]; null until
  // the row is tabulated.
  std::vector<std::unique_ptr<double[]>> table_;
  // H(j, j', z) from T and c, for any z (4 values αβ).
  void averaged_kernel(int j, int js, double z, double out[4]) const;
  double extent_ = -1;       // of the current H table
  int J_ = 0, Z_ = 0;        // H covers |j − j'| ≤ J_ and |z| ≤ Z_
  std::vector<float> H_;     // H at [((j S + z sample) (2J+1) + j' − j + J) 4 + 2α + β], S = 2 Z kPhaseSamples + 1
};

}  // namespace rbc
