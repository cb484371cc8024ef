#pragma once
// The Green's function of step 4's Helmholtz operator A (fluid/diffusion.hpp), tabulated once:
//
//   G(k, k') = (A⁻¹)_{k k'},   k = r nx + i  (interior row r = j − 1, column i).
//
// A commutes with the shift in x1 (periodic), so G depends on i − i' (mod nx), r and r' only:
// one fast solve of A x = e_(0, r') per source row r' gives the whole table, nx × rows × rows
// values (65 MB for the 320 × 159 interior of the study's wide channel at h = 0.3125 µm). A is
// symmetric, and so is G.
//
// Moving rigid bodies (rigid_disks.hpp) need entries of A⁻¹ between their collocation points at
// every step, where they are; a table lookup replaces a fast solve per point. G decays away from
// the source over the screening length √(μΔt/ρ) (1.5 µm at Δt = 2e-6 s), which is why the disks'
// capacitance systems are nearly independent of each other when the disks are apart.
#include <cstddef>
#include <vector>

#include "fast_solvers/periodic_banded_solver.hpp"

namespace rbc {

class HelmholtzGreen {
 public:
  explicit HelmholtzGreen(PeriodicBandedSolver& A);
  // (A⁻¹)_{k k'} for interior-row indices k, k' (x1 fastest).
  double operator()(int k, int kp) const { return at(k / nx_, k % nx_, kp / nx_, kp % nx_); }
  // The same entry by row and column, (r, i) and (r', i'): no divisions, for callers that look up
  // many pairs of the same points (the disks' capacitance systems at every step).
  double at(int r, int i, int rp, int ip) const {
    int d = i - ip;
    if (d < 0) d += nx_;
    return g_[(std::size_t(rp) * rows_ + std::size_t(r)) * std::size_t(nx_) + std::size_t(d)];
  }
  int nx() const { return nx_; }
  int rows() const { return rows_; }
  std::size_t bytes() const { return g_.size() * sizeof(double); }
  double setup_seconds() const { return setup_seconds_; }

 private:
  int nx_, rows_;
  std::vector<double> g_;  // [r'][r][d]
  double setup_seconds_ = 0;
};

}  // namespace rbc
