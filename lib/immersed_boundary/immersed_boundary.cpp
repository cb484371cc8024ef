#include "immersed_boundary/immersed_boundary.hpp"

#include "immersed_boundary/peskin_delta.hpp"

namespace rbc {

void node_stencils(const ChannelMesh& m, const Points& r, std::vector<NodeStencil>& st) {
  st.resize(r.size());
  for (std::size_t k = 0; k < r.size(); ++k) {
    st[k].i0 = m.wrap(peskin_weights(r[k].x() / m.h, st[k].wx));
    st[k].j0 = peskin_weights(r[k].y() / m.h, st[k].wy);
  }
}

namespace {

// (10) for the nodes' stencils: adds c φ_a φ_b F_k to the nodes of the interior rows j = 1..ny−1
// of (f1, f2) (x1 fastest; F_k's components at F[2k], F[2k + 1]); the force spread onto the wall
// rows and beyond is dropped (the wall velocity is prescribed). c = 1/h² gives f_B itself
// (δ_h δ_h = φ φ / h²), c = 1 gives h² f_B (the right-hand sides of step 4).
inline void spread_interior(const ChannelMesh& m, const std::vector<NodeStencil>& st, const double* F, double c, double* f1,
                            double* f2) {
  for (std::size_t k = 0; k < st.size(); ++k) {
    const NodeStencil& s = st[k];
    for (int b = 0; b < 4; ++b) {
      const int j = s.j0 + b;
      if (j <= 0 || j >= m.ny) continue;  // walls and beyond: dropped
      const std::size_t row = std::size_t(j - 1) * m.nx;
      const double fx = F[2 * k], fy = F[2 * k + 1], wy = s.wy[b];
      if (s.i0 + 3 < m.nx) {  // four consecutive nodes (the common case: the compiler vectorises it)
        double* __restrict g1 = f1 + row + s.i0;
        double* __restrict g2 = f2 + row + s.i0;
#pragma omp simd
        for (int a = 0; a < 4; ++a) {
          const double w = s.wx[a] * wy * c;
          g1[a] += w * fx;
          g2[a] += w * fy;
        }
        continue;
      }
      for (int a = 0, i = s.i0; a < 4; ++a, i = i + 1 == m.nx ? 0 : i + 1) {  // the stencil wraps around x1
        const double w = s.wx[a] * wy * c;
        f1[row + i] += w * fx;
        f2[row + i] += w * fy;
      }
    }
  }
}

}  // namespace

void spread_forces(const ChannelMesh& m, const std::vector<NodeStencil>& st, const Points& F, VelocityField& field) {
  if (st.empty()) return;
  spread_interior(m, st, F[0].data(), 1.0 / (m.h * m.h), field.u1.data() + m.nx, field.u2.data() + m.nx);
}

void spread_forces_interior(const ChannelMesh& m, const std::vector<NodeStencil>& st, const double* F, double* f1, double* f2) {
  spread_interior(m, st, F, 1.0, f1, f2);
}

namespace {

// (13) at one membrane node: U = Σ_x h² u(x) δ_h δ_h = Σ_{a,b} φ_a φ_b u(x_ab) over the node's
// stencil s, rows beyond the walls left out. nodes(b, n) puts the places in (v1, v2) of the
// stencil's row b into n[0..3], or returns false for a row beyond the walls.
template <class RowNodes>
Eigen::Vector2d interpolate_at(const NodeStencil& s, const double* v1, const double* v2, RowNodes nodes) {
  Eigen::Vector2d v = Eigen::Vector2d::Zero();
  for (int b = 0; b < 4; ++b) {
    std::size_t n[4];
    if (!nodes(b, n)) continue;
    for (int a = 0; a < 4; ++a) {
      const double w = s.wx[a] * s.wy[b];
      v += w * Eigen::Vector2d(v1[n[a]], v2[n[a]]);
    }
  }
  return v;
}

}  // namespace

void interpolate_velocity(const ChannelMesh& m, const VelocityField& u, const std::vector<NodeStencil>& st, Points& U) {
  U.assign(st.size(), Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < st.size(); ++k) {
    const NodeStencil& s = st[k];
    U[k] = interpolate_at(s, u.u1.data(), u.u2.data(), [&](int b, std::size_t n[4]) {
      const int j = s.j0 + b;
      if (j < 0 || j > m.ny) return false;  // beyond the walls: no mesh node
      const std::size_t row = std::size_t(j) * m.nx;
      for (int a = 0, i = s.i0; a < 4; ++a, i = i + 1 == m.nx ? 0 : i + 1) n[a] = row + i;
      return true;
    });
  }
}

void spread_forces(const ChannelMesh& m, const Points& r, const Points& F, VelocityField& field) {
  std::vector<NodeStencil> st;
  node_stencils(m, r, st);
  spread_forces(m, st, F, field);
}

void interpolate_velocity(const ChannelMesh& m, const VelocityField& u, const Points& r, Points& U) {
  std::vector<NodeStencil> st;
  node_stencils(m, r, st);
  interpolate_velocity(m, u, st, U);
}

bool StencilFootprint::build(const ChannelMesh& m, const std::vector<std::vector<NodeStencil>>& stencils, std::size_t max_nodes) {
  const std::size_t mesh_nodes = std::size_t(m.nx) * (m.ny + 1);
  if (slot_of_.size() != mesh_nodes) slot_of_.assign(mesh_nodes, -1);
  for (const auto& [i, j] : nodes_) slot_of_[std::size_t(j) * m.nx + i] = -1;  // the last build's
  nodes_.clear();
  slots_.resize(stencils.size());
  for (std::size_t c = 0; c < stencils.size(); ++c) {
    slots_[c].assign(16 * stencils[c].size(), -1);
    for (std::size_t k = 0; k < stencils[c].size(); ++k) {
      const NodeStencil& s = stencils[c][k];
      for (int b = 0; b < 4; ++b) {
        const int j = s.j0 + b;
        if (j < 0 || j > m.ny) continue;
        for (int a = 0, i = s.i0; a < 4; ++a, i = i + 1 == m.nx ? 0 : i + 1) {
          int& slot = slot_of_[std::size_t(j) * m.nx + i];
          if (slot < 0) {
            if (nodes_.size() == max_nodes) return false;
            slot = int(nodes_.size());
            nodes_.push_back({i, j});
          }
          slots_[c][16 * k + 4 * b + a] = slot;
        }
      }
    }
  }
  return true;
}

void StencilFootprint::interpolate(int c, const std::vector<NodeStencil>& st, const double* v1, const double* v2, Points& U) const {
  U.assign(st.size(), Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < st.size(); ++k) {
    const int* slot = &slots_[c][16 * k];
    U[k] = interpolate_at(st[k], v1, v2, [&](int b, std::size_t n[4]) {
      if (slot[4 * b] < 0) return false;  // beyond the walls
      for (int a = 0; a < 4; ++a) n[a] = std::size_t(slot[4 * b + a]);
      return true;
    });
  }
}

}  // namespace rbc
