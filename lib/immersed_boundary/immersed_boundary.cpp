#include "immersed_boundary/immersed_boundary.hpp"

#include "immersed_boundary/peskin_delta.hpp"

namespace rbc {

namespace {
// Stencil of node position p: first column/row and weights φ in each direction.
struct Stencil {
  int i0, j0;
  double wx[4], wy[4];
};
Stencil stencil(const ChannelMesh& m, const Eigen::Vector2d& p) {
  Stencil s;
  s.i0 = peskin_weights(p.x() / m.h, s.wx);
  s.j0 = peskin_weights(p.y() / m.h, s.wy);
  return s;
}
}  // namespace

void spread_forces(const ChannelMesh& m, const Points& r, const Points& F, VelocityField& field) {
  // f_B at node x: Σ_i F_i φ(..)φ(..)/h² (the 1/h² is δ_h δ_h).
  const double inv_h2 = 1.0 / (m.h * m.h);
  for (std::size_t k = 0; k < r.size(); ++k) {
    const Stencil s = stencil(m, r[k]);
    for (int b = 0; b < 4; ++b) {
      const int j = s.j0 + b;
      if (j <= 0 || j >= m.ny) continue;  // walls and beyond: dropped
      for (int a = 0; a < 4; ++a) {
        const double w = s.wx[a] * s.wy[b] * inv_h2;
        const std::size_t n = m.v(s.i0 + a, j);
        field.u1[n] += w * F[k].x();
        field.u2[n] += w * F[k].y();
      }
    }
  }
}

void interpolate_velocity(const ChannelMesh& m, const VelocityField& u, const Points& r, Points& U) {
  // U(r) = Σ_x h² u(x) δ_h δ_h = Σ_x u(x) φ φ.
  U.assign(r.size(), Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < r.size(); ++k) {
    const Stencil s = stencil(m, r[k]);
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    for (int b = 0; b < 4; ++b) {
      const int j = s.j0 + b;
      if (j < 0 || j > m.ny) continue;  // beyond the walls: no mesh node
      for (int a = 0; a < 4; ++a) {
        const double w = s.wx[a] * s.wy[b];
        const std::size_t n = m.v(s.i0 + a, j);
        v += w * Eigen::Vector2d(u.u1[n], u.u2[n]);
      }
    }
    U[k] = v;
  }
}

}  // namespace rbc
