#include "immersed_boundary/step_mobility.hpp"

#include <algorithm>

#include "immersed_boundary/peskin_delta.hpp"

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

namespace {
struct NodeStencil {
  int i0, j0;  // first column (unwrapped) and first row of the 4 × 4 stencil
  double wx[4], wy[4];
};
}  // namespace

void StepMobility::matrix(const Points& r, Eigen::MatrixXd& M) const {
  const int n = int(r.size()), nx = m_.nx;
  std::vector<NodeStencil> st(n);
  for (int k = 0; k < n; ++k) {
    st[k].i0 = peskin_weights(r[k].x() / m_.h, st[k].wx);
    st[k].j0 = peskin_weights(r[k].y() / m_.h, st[k].wy);
  }
  M.resize(2 * n, 2 * n);
  for (int k = 0; k < n; ++k) {
    const NodeStencil& a = st[k];
    for (int l = 0; l < n; ++l) {
      const NodeStencil& b = st[l];
      // x1 weights by column offset o = px − qx + 3 and by the parity of the source column
      // i0_l + qx: c[o][8] holds the weight under each of the 8 table values.
      const int parity0 = ((b.i0 % 2) + 2) % 2;
      double c[7][8] = {};
      for (int px = 0; px < 4; ++px)
        for (int qx = 0; qx < 4; ++qx) {
          const double w = a.wx[px] * b.wx[qx];
          double* cc = c[px - qx + 3] + 4 * ((parity0 + qx) % 2);
          for (int v = 0; v < 4; ++v) cc[v] += w;
        }
      int col[7];  // i_k − i_l (source column i0_l + qx, offset o) wrapped into 0..nx−1
      const int d0 = ((a.i0 - b.i0 - 3) % nx + nx) % nx;
      for (int o = 0; o < 7; ++o) col[o] = (d0 + o) % nx;
      double sum[8] = {};
      for (int p = 0; p < 4; ++p) {
        const int j = a.j0 + p - 1;  // interior row index of node row j0 + p
        if (j < 0 || j >= rows_) continue;
        for (int q = 0; q < 4; ++q) {
          const int js = b.j0 + q - 1;
          if (js < 0 || js >= rows_) continue;
          const double w = a.wy[p] * b.wy[q];
          double s[8] = {};
          for (int o = 0; o < 7; ++o) {
            const double* g = entry(j, js, col[o]);
            for (int v = 0; v < 8; ++v) s[v] += c[o][v] * g[v];
          }
          for (int v = 0; v < 8; ++v) sum[v] += w * s[v];
        }
      }
      for (int alpha = 0; alpha < 2; ++alpha)
        for (int beta = 0; beta < 2; ++beta)
          M(2 * k + alpha, 2 * l + beta) = sum[2 * alpha + beta] + sum[4 + 2 * alpha + beta];
    }
  }
}

}  // namespace rbc
