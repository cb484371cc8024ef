#pragma once
// Step 3 of the Lie scheme (the study's Section 2.4): advection by the wave-like equation method of
// Dean & Glowinski. With V = u^{n+1/3} frozen and divergence-free, ∂u/∂t + (V·∇)u = 0 implies
//
//   ∂²u/∂t² − ∇·((V·∇u) V) = 0,   u(tⁿ) = u^{n+1/3},   ∂u/∂t(tⁿ) = −(V·∇) u^{n+1/3},
//
// whose weak form with the lumped mass M is  M ü + A u = 0,  A_nm = ∫ (V·∇φ_m)(V·∇φ_n)
// (the wall terms vanish: u is prescribed there and V·n = 0). We take Q explicit centred steps
// of τ = Δt/Q; the first one is the Taylor step u¹ = u⁰ + τ u̇⁰ − τ²/2 M⁻¹ A u⁰, with
// M u̇⁰ = −C u⁰, C_nm = ∫ (V·∇φ_m) φ_n. Integrals use V at the triangle's centroid.
// The scheme is stable for τ |V|_max / h below about 1; we require at most `kAdvectiveCfl`.
#include <vector>

#include "mesh/channel_mesh.hpp"

namespace rbc {

inline constexpr double kAdvectiveCfl = 0.5;  // τ |V|_max / h allowed (half the stability limit)

class WaveLikeAdvection {
 public:
  explicit WaveLikeAdvection(const ChannelMesh& mesh);
  // Advects u (in place, both components) by V over dt in Q substeps. u and V may alias.
  void advect(const VelocityField& V, VelocityField& u, double dt, int substeps);

 private:
  // For both components c: minv_a[c] = M⁻¹ A f[c], and (if given) minv_c[c] = −M⁻¹ C f[c],
  // on the interior nodes.
  void apply(std::vector<double>* const f[2], std::vector<double>* minv_a, std::vector<double>* minv_c);
  ChannelMesh m_;
  std::vector<double> vl_[2], vu_[2];  // V at the centroids of the lower/upper triangles of each square
  std::vector<double> prev_[2], cur_[2], next_[2], acc_[2], vel_[2];
};

}  // namespace rbc
