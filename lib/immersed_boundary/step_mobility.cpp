#include "immersed_boundary/step_mobility.hpp"

#include <algorithm>

#include <omp.h>

#include "immersed_boundary/immersed_boundary.hpp"

namespace rbc {

StepMobility::StepMobility(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection,
                           double rho, double dt)
    : m_(mesh), rows_(mesh.ny - 1), table_(std::size_t(8) * mesh.nx * rows_ * rows_, 0.0) {
  const int nx = m_.nx;
  const std::size_t plane = std::size_t(nx) * rows_;
  VelocityField u(mesh);
  std::vector<double> p(mesh.pressure_nodes(), 0.0), b(plane);
  for (int parity = 0; parity < 2; ++parity)
    for (int beta = 0; beta < 2; ++beta)
      for (int js = 0; js < rows_; ++js) {
        // P A⁻¹ applied to a unit value in component β at node (parity, js + 1).
        std::fill(u.u1.begin(), u.u1.end(), 0.0);
        std::fill(u.u2.begin(), u.u2.end(), 0.0);
        std::fill(b.begin(), b.end(), 0.0);
        b[std::size_t(js) * nx + parity] = 1.0;
        diffusion.solve_interior(b.data());
        std::copy(b.begin(), b.end(), (beta == 0 ? u.u1 : u.u2).begin() + nx);
        std::fill(p.begin(), p.end(), 0.0);
        projection.project(u, p, rho, dt);
        for (int alpha = 0; alpha < 2; ++alpha) {
          const std::vector<double>& f = alpha == 0 ? u.u1 : u.u2;
          for (int j = 0; j < rows_; ++j)
            for (int i = 0; i < nx; ++i)  // stored by column offset i − parity
              entry(j, js, (i - parity + nx) % nx)[4 * parity + 2 * alpha + beta] = f[std::size_t(j + 1) * nx + i];
        }
      }
}

void StepMobility::matrix(const Points& r, Eigen::MatrixXd& M) const {
  // Two stages. (a) The response of every source node l at the footprint (the mesh nodes under
  // any node's stencil): R_l(x) = Σ_{q, qx} φ_l T(x − source); (b) M_kl = Σ_{x ∈ stencil k} φ_k(x) R_l(x).
  // 64 multiply-adds per (l, footprint node) and per pair, instead of 16 × 7 × 8 per pair.
  const int n = int(r.size()), nx = m_.nx;
  std::vector<NodeStencil> st;
  node_stencils(m_, r, st);
  // The footprint: interior mesh nodes (column mod nx, interior row) under some stencil; slot
  // of each stencil point (−1 for rows on or beyond the walls).
  std::vector<int> slot(std::size_t(n) * 16, -1);
  std::vector<std::pair<int, int>> points;  // (column, interior row)
  std::vector<int> index(std::size_t(nx) * rows_, -1);
  for (int k = 0; k < n; ++k)
    for (int p = 0; p < 4; ++p) {
      const int j = st[k].j0 + p - 1;
      if (j < 0 || j >= rows_) continue;
      for (int px = 0; px < 4; ++px) {
        const int i = st[k].i0 + px < nx ? st[k].i0 + px : st[k].i0 + px - nx;
        int& id = index[std::size_t(j) * nx + i];
        if (id < 0) { id = int(points.size()); points.push_back({i, j}); }
        slot[std::size_t(k) * 16 + p * 4 + px] = id;
      }
    }
  const int F = int(points.size());
  std::vector<double> R(std::size_t(F) * n * 4);  // R_l(x) at [(x n + l) 4 + v]
#pragma omp parallel for schedule(static) if (!omp_in_parallel())
  for (int l = 0; l < n; ++l) {
    const NodeStencil& b = st[l];
    double w[16];  // φ_l's weights, wy[q] wx[qx]
    for (int q = 0; q < 4; ++q)
      for (int qx = 0; qx < 4; ++qx) w[q * 4 + qx] = b.wy[q] * b.wx[qx];
    for (int x = 0; x < F; ++x) {
      const auto [i, j] = points[x];
      int d0 = i - b.i0;  // column offset to the first source column, mod nx
      d0 += d0 < 0 ? nx : 0;
      double acc[4] = {0, 0, 0, 0};
      for (int q = 0; q < 4; ++q) {
        const int js = b.j0 + q - 1;
        if (js < 0 || js >= rows_) continue;
        const double* plane = entry(j, js, 0);
        for (int qx = 0; qx < 4; ++qx) {
          int di = d0 - qx;  // i − (i0 + qx) mod nx
          di += di < 0 ? nx : 0;
          const double* g = plane + std::size_t(di) * 8 + 4 * ((b.i0 + qx) & 1);
          const double wq = w[q * 4 + qx];
          for (int v = 0; v < 4; ++v) acc[v] += wq * g[v];
        }
      }
      for (int v = 0; v < 4; ++v) R[(std::size_t(x) * n + l) * 4 + v] = acc[v];
    }
  }
  M.resize(2 * n, 2 * n);
#pragma omp parallel if (!omp_in_parallel())
  {
  std::vector<double> sum(std::size_t(n) * 4);  // row pair k of M, (l, v) with v = 2α + β
#pragma omp for schedule(static)
  for (int k = 0; k < n; ++k) {
    const NodeStencil& a = st[k];
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int p = 0; p < 4; ++p)
      for (int px = 0; px < 4; ++px) {
        const int x = slot[std::size_t(k) * 16 + p * 4 + px];
        if (x < 0) continue;
        const double w = a.wy[p] * a.wx[px];
        const double* Rx = &R[std::size_t(x) * n * 4];  // R at footprint point x for every l
        for (int lv = 0; lv < 4 * n; ++lv) sum[lv] += w * Rx[lv];
      }
    for (int l = 0; l < n; ++l) {
      M(2 * k, 2 * l) = sum[4 * l];
      M(2 * k, 2 * l + 1) = sum[4 * l + 1];
      M(2 * k + 1, 2 * l) = sum[4 * l + 2];
      M(2 * k + 1, 2 * l + 1) = sum[4 * l + 3];
    }
  }
  }
}

}  // namespace rbc
