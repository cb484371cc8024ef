#pragma once
// The divergence matrix B of fem/p1_operators.hpp applied as stencils (no stored matrix).
//
// On a fine triangle T, ∇·u is constant and the coarse pressure basis q_Q is linear, so
//   (B u)_Q = Σ_T |T| (∇·u)_T (q_Q(a) + q_Q(b) + q_Q(c))/3 = Σ_n q_Q(n) d_n,
//   d_n = Σ_{T ∋ n} |T| (∇·u)_T / 3                    (a fine "divergence moment"),
// i.e. B = R D: a fine stencil D followed by the restriction R with the weights q_Q(n) of the
// P1-iso-P2 refinement (1 at the coarse node, 1/2 at the six fine neighbours along the coarse
// edges). Its transpose is Bᵀ = Dᵀ Rᵀ: prolongate p to the fine nodes, average over each
// triangle, and take the weighted basis gradients.
#include <vector>

#include "mesh/channel_mesh.hpp"

namespace rbc {

class DivergenceStencil {
 public:
  explicit DivergenceStencil(const ChannelMesh& mesh);
  // div[Q] = (B u)_Q over all coarse nodes.
  void apply(const std::vector<double>& u1, const std::vector<double>& u2, std::vector<double>& div) const;
  // (g1, g2) = Bᵀ p on the interior velocity nodes (wall rows set to 0).
  void apply_transpose(const std::vector<double>& p, std::vector<double>& g1, std::vector<double>& g2) const;
  // out = u + c Bᵀ p in one sweep (the wall rows: u), for the projection's velocity update; each
  // value is u + c g with g as apply_transpose gives it. out may be u.
  void add_transpose(const std::vector<double>& p, double c, const std::vector<double>& u1, const std::vector<double>& u2,
                     std::vector<double>& out1, std::vector<double>& out2) const;
  // (g1, g2) = (Bᵀ p) at the one interior node (i, j), 0 ≤ i < nx, 1 ≤ j ≤ ny − 1, by the
  // sweep's expressions (its values to round-off: the sweep rounds each triangle's sum as it
  // stores it), for callers that need Bᵀ p at a few nodes only.
  void transpose_at(const std::vector<double>& p, int i, int j, double& g1, double& g2) const;

 private:
  ChannelMesh m_;
  // Bᵀ p row by row; store(j, i, g1, g2) receives the values of interior node (i, j).
  template <class Store>
  void transpose_rows(const std::vector<double>& p, Store store) const;
};

}  // namespace rbc
