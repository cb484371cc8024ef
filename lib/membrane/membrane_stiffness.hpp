#pragma once
// The stiffness of the spring membrane, for the linearly implicit coupling (semi_implicit_coupling.hpp):
//
//   F(r + δr) ≈ F(r) − K δr,     K ≈ ∂²(E_l + E_b + E_s)/∂r²                      (5)-(8)
//
// We keep the positive semi-definite part of the Hessian, so that the implicit step can only
// damp (a backward-Euler step of dr/dt = −M K r with M, K ⪰ 0 has amplification 1/(1 + Δt λ)):
//
//   spring i, d = r_{i+1} − r_i, e = d/|d|:  (k_l/l0²) e eᵀ + (k_l (l − l0)⁺/(l0² l)) (I − e eᵀ)
//                       (exact for a stretched spring; a compressed one keeps the axial part)
//   bending node i:     k_b ∇t ∇tᵀ        (Gauss–Newton: drops k_b t ∇²t, t = tan(θ/2) ≈ π/N)
//   area penalty:       (k_s/s_e²) ∇s ∇sᵀ  (Gauss–Newton: exact at s = s_e)
//
// K is 2N × 2N with unknowns ordered (x_1, y_1, x_2, …), units N/m per m. The springs and bending
// couple each node to its two neighbours on either side (a periodic band of 2 × 2 blocks); the
// area term is rank one, c g gᵀ. We keep the two apart, so that K v and M K cost O(N) and O(N²),
// not O(N²), O(N³). (The band is built for every cell at every semi-implicit step: stored as
// blocks, not as a general sparse matrix, it costs a fifth; sums run in the order a sparse
// matrix would take them, so results are the same bits.)
#include <vector>

#include <Eigen/Dense>

#include "membrane/spring_membrane.hpp"

namespace rbc {

struct MembraneStiffness {
  // Springs and bending: the 2 × 2 block coupling node i to node i + o (mod N), o = −2 … 2, at
  // band[5 i + o + 2].
  std::vector<Eigen::Matrix2d> band;
  Eigen::VectorXd area_gradient;     // g = ∂s/∂r (empty without the area penalty)
  double area_coefficient = 0;       // c = k_s / s_e²

  Eigen::VectorXd apply(const Eigen::VectorXd& v) const;         // K v
  Eigen::MatrixXd right_multiply(const Eigen::MatrixXd& M) const;  // M K
  Eigen::MatrixXd dense() const;                                   // K (for tests)
};

MembraneStiffness membrane_stiffness(const MembraneModel& m, const Points& r, double target_area);

}  // namespace rbc
