#pragma once
// Finite-element matrices of the study's discretisation (its Section 2.4) on the uniform
// triangulation of ChannelMesh. With every square cut by the same diagonal, they are stencils.
//
//   lumped mass      M_nn = ∫ φ_n = h² (interior node), h²/2 (wall node)
//   P1 stiffness     K_nm = ∫ ∇φ_n · ∇φ_m   = the 5-point Laplacian (4 on the node, −1 on each
//                    of its four neighbours) in the interior; natural (Neumann) rows on the walls
//   divergence       B_qn = ∫ q_Q ∇·φ_n     with q_Q the P1 basis of T_2h (pressure) and φ_n the
//                    P1 basis of T_h (velocity, one column per component and node)
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "mesh/channel_mesh.hpp"

namespace rbc {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// K on a periodic grid of nx × (ny + 1) nodes with spacing h (h cancels in 2D), assembled over
// triangles, with natural boundary conditions on rows 0 and ny.
SparseMatrix assemble_p1_stiffness(int nx, int ny);

// B: pressure nodes × (2 × velocity nodes); columns [u1 at every node, then u2 at every node].
// On a fine triangle T, ∇·u is constant and q is linear, so ∫_T q ∇·u = |T| (∇·u)_T q(centroid).
SparseMatrix assemble_divergence(const ChannelMesh& mesh);

// The P1 basis of T_2h at the fine node (i, j) of T_h (i in 0..nx-1): w gets (pressure node,
// value) pairs. A fine node is a coarse node (1), the midpoint of a coarse horizontal or vertical
// edge (½ each end), or the midpoint of a coarse diagonal, from (2I+2, 2J) to (2I, 2J+2), the
// direction of the fine diagonals (½ each end).
void coarse_weights_at(const ChannelMesh& mesh, int i, int j, std::vector<std::pair<std::size_t, double>>& w);

// Lumped mass of the velocity nodes (wall rows included): h² inside, h²/2 on the walls.
double lumped_mass(const ChannelMesh& mesh, int j);

}  // namespace rbc
