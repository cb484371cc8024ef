#include "fem/p1_operators.hpp"

#include <array>
#include <vector>

namespace rbc {

namespace {
// The two triangles of square (i, j): vertex offsets and the gradients of their P1 basis
// functions, in units of 1/h.
struct Triangle {
  std::array<std::array<int, 2>, 3> v;
  std::array<std::array<double, 2>, 3> grad;
};
constexpr std::array<Triangle, 2> kTriangles = {{
    {{{{0, 0}, {1, 0}, {0, 1}}}, {{{-1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}}}},   // lower
    {{{{1, 0}, {1, 1}, {0, 1}}}, {{{0.0, -1.0}, {1.0, 1.0}, {-1.0, 0.0}}}},   // upper
}};
}  // namespace

SparseMatrix assemble_p1_stiffness(int nx, int ny) {
  std::vector<Eigen::Triplet<double>> t;
  auto node = [nx](int i, int j) { return j * nx + wrap_index(i, nx); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (const Triangle& T : kTriangles)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            // |T| ∇φ_a · ∇φ_b with |T| = h²/2 and gradients O(1/h): h cancels.
            const double k = 0.5 * (T.grad[a][0] * T.grad[b][0] + T.grad[a][1] * T.grad[b][1]);
            if (k != 0.0) t.emplace_back(node(i + T.v[a][0], j + T.v[a][1]), node(i + T.v[b][0], j + T.v[b][1]), k);
          }
  SparseMatrix K(nx * (ny + 1), nx * (ny + 1));
  K.setFromTriplets(t.begin(), t.end());
  K.prune(0.0);
  return K;
}

void coarse_weights_at(const ChannelMesh& m, int i, int j, std::vector<std::pair<std::size_t, double>>& w) {
  w.clear();
  const bool ie = (i % 2 == 0), je = (j % 2 == 0);
  if (ie && je) w.push_back({m.p(i / 2, j / 2), 1.0});
  else if (!ie && je) { w.push_back({m.p((i - 1) / 2, j / 2), 0.5}); w.push_back({m.p((i + 1) / 2, j / 2), 0.5}); }
  else if (ie && !je) { w.push_back({m.p(i / 2, (j - 1) / 2), 0.5}); w.push_back({m.p(i / 2, (j + 1) / 2), 0.5}); }
  else { w.push_back({m.p((i + 1) / 2, (j - 1) / 2), 0.5}); w.push_back({m.p((i - 1) / 2, (j + 1) / 2), 0.5}); }
}

SparseMatrix assemble_divergence(const ChannelMesh& m) {
  const std::size_t nv = m.velocity_nodes();
  const double area = 0.5 * m.h * m.h;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<std::pair<std::size_t, double>> w;
  for (int j = 0; j < m.ny; ++j)
    for (int i = 0; i < m.nx; ++i)
      for (const Triangle& T : kTriangles) {
        // q at the centroid is the mean of q at the three vertices.
        std::vector<std::pair<std::size_t, double>> qc;
        for (int a = 0; a < 3; ++a) {
          coarse_weights_at(m, m.wrap(i + T.v[a][0]), j + T.v[a][1], w);
          for (auto [Q, c] : w) qc.push_back({Q, c / 3.0});
        }
        for (int b = 0; b < 3; ++b) {
          const std::size_t n = m.v(i + T.v[b][0], j + T.v[b][1]);
          for (auto [Q, c] : qc) {
            // ∇·(φ_n e1) = ∂φ_n/∂x1,  ∇·(φ_n e2) = ∂φ_n/∂x2.
            if (T.grad[b][0] != 0.0) t.emplace_back(Q, n, area * c * T.grad[b][0] / m.h);
            if (T.grad[b][1] != 0.0) t.emplace_back(Q, nv + n, area * c * T.grad[b][1] / m.h);
          }
        }
      }
  SparseMatrix B(m.pressure_nodes(), 2 * nv);
  B.setFromTriplets(t.begin(), t.end());
  B.prune(m.h, 1e-12);  // drop entries that cancel to round-off
  return B;
}

double lumped_mass(const ChannelMesh& m, int j) {
  return (j == 0 || j == m.ny) ? 0.5 * m.h * m.h : m.h * m.h;
}

}  // namespace rbc
