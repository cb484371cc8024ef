#include "fluid/wave_like_advection.hpp"

namespace rbc {

WaveLikeAdvection::WaveLikeAdvection(const ChannelMesh& mesh) : m_(mesh) {
  const std::size_t cells = std::size_t(mesh.nx) * mesh.ny;
  for (int c = 0; c < 2; ++c) { vl_[c].assign(cells, 0.0); vu_[c].assign(cells, 0.0); }
  gl_.assign(cells, 0.0);
  gu_.assign(cells, 0.0);
  const std::size_t n = mesh.velocity_nodes();
  for (auto* v : {&prev_, &cur_, &next_, &acc_, &vel_}) v->assign(n, 0.0);
}

void WaveLikeAdvection::apply(const std::vector<double>& f, std::vector<double>& minv_a,
                              std::vector<double>* minv_c) const {
  const int nx = m_.nx, ny = m_.ny;
  const double inv_h = 1.0 / m_.h;
  // Per triangle: g_T = V_T · ∇f_T.
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * nx + i;
      const int ip = (i + 1 == nx) ? 0 : i + 1;
      const double f00 = f[m_.v(i, j)], f10 = f[m_.v(ip, j)], f01 = f[m_.v(i, j + 1)], f11 = f[m_.v(ip, j + 1)];
      gl_[c] = (vl_[0][c] * (f10 - f00) + vl_[1][c] * (f01 - f00)) * inv_h;
      gu_[c] = (vu_[0][c] * (f11 - f01) + vu_[1][c] * (f11 - f10)) * inv_h;
    }
  // Per interior node, gather from its six triangles:
  //   (A f)_n = |T| Σ_T g_T (V_T·∇φ_n),   (C f)_n = |T|/3 Σ_T g_T,   M_nn = h², |T| = h²/2.
#pragma omp parallel for schedule(static)
  for (int j = 1; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int im = (i == 0) ? nx - 1 : i - 1;
      const std::size_t a = std::size_t(j) * nx + i;        // square (i, j): node is lower vertex 0
      const std::size_t b = std::size_t(j) * nx + im;       // square (i-1, j): lower vertex 1, upper vertex 0
      const std::size_t c = std::size_t(j - 1) * nx + i;    // square (i, j-1): lower vertex 2, upper vertex 2
      const std::size_t d = std::size_t(j - 1) * nx + im;   // square (i-1, j-1): upper vertex 1
      const double s = gl_[a] * (-vl_[0][a] - vl_[1][a]) + gl_[b] * vl_[0][b] + gl_[c] * vl_[1][c] +
                       gu_[b] * (-vu_[1][b]) + gu_[d] * (vu_[0][d] + vu_[1][d]) + gu_[c] * (-vu_[0][c]);
      const std::size_t n = m_.v(i, j);
      minv_a[n] = 0.5 * s * inv_h;  // |T|/M = 1/2, one more 1/h from ∇φ
      if (minv_c) (*minv_c)[n] = -(gl_[a] + gl_[b] + gl_[c] + gu_[b] + gu_[d] + gu_[c]) / 6.0;
    }
}

void WaveLikeAdvection::advect(const VelocityField& V, VelocityField& u, double dt, int substeps) {
  const int nx = m_.nx, ny = m_.ny;
  // Freeze V at the triangle centroids (a copy, so that u may alias V).
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = std::size_t(j) * nx + i;
      const std::size_t n00 = m_.v(i, j), n10 = m_.v(i + 1, j), n01 = m_.v(i, j + 1), n11 = m_.v(i + 1, j + 1);
      vl_[0][c] = (V.u1[n00] + V.u1[n10] + V.u1[n01]) / 3.0;
      vl_[1][c] = (V.u2[n00] + V.u2[n10] + V.u2[n01]) / 3.0;
      vu_[0][c] = (V.u1[n10] + V.u1[n11] + V.u1[n01]) / 3.0;
      vu_[1][c] = (V.u2[n10] + V.u2[n11] + V.u2[n01]) / 3.0;
    }
  const double tau = dt / substeps;
  const std::size_t first = std::size_t(nx), last = std::size_t(ny) * nx;  // interior nodes [first, last)
  for (std::vector<double>* comp : {&u.u1, &u.u2}) {
    std::vector<double>& f = *comp;
    // Taylor start: u¹ = u⁰ + τ u̇⁰ − τ²/2 M⁻¹A u⁰.
    prev_ = f;
    apply(prev_, acc_, &vel_);
    cur_ = prev_;
    for (std::size_t n = first; n < last; ++n) cur_[n] = prev_[n] + tau * vel_[n] - 0.5 * tau * tau * acc_[n];
    // Centred steps: u^{q+1} = 2u^q − u^{q−1} − τ² M⁻¹A u^q.
    for (int q = 1; q < substeps; ++q) {
      apply(cur_, acc_, nullptr);
      next_ = cur_;
      for (std::size_t n = first; n < last; ++n) next_[n] = 2.0 * cur_[n] - prev_[n] - tau * tau * acc_[n];
      std::swap(prev_, cur_);
      std::swap(cur_, next_);
    }
    f = cur_;
  }
}

}  // namespace rbc
