#include "fluid/wave_like_advection.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <omp.h>

#include "fluid/detail/advection_kernels.hpp"

namespace rbc {

WaveLikeAdvection::WaveLikeAdvection(const ChannelMesh& mesh) : m_(mesh) {
  const std::size_t cells = std::size_t(mesh.nx) * mesh.ny;
  for (int c = 0; c < 2; ++c) {
    vl_[c].assign(cells, 0.0);
    vu_[c].assign(cells, 0.0);
    const std::size_t n = mesh.velocity_nodes();
    for (auto* v : {&prev_[c], &cur_[c], &next_[c], &acc_[c], &vel_[c]}) v->assign(n, 0.0);
  }
}

void WaveLikeAdvection::apply(std::vector<double>* const f[2], std::vector<double>* minv_a, std::vector<double>* minv_c) {
  const int nx = m_.nx, ny = m_.ny;
  const double inv_h = 1.0 / m_.h;
  // Per triangle and component: g_T = V_T · ∇f_T (triangle_row), a row of squares at a time; then
  // per interior node, gather from its six triangles:
  //   (A f)_n = |T| Σ_T g_T (V_T·∇φ_n),   (C f)_n = |T|/3 Σ_T g_T,   M_nn = h², |T| = h²/2.
  // Around node (i, j): a = square (i, j), b = (i−1, j), c = (i, j−1), d = (i−1, j−1); the node
  // is vertex 0 of lower a, 1 of lower b, 2 of lower c, 0 of upper b, 1 of upper d, 2 of upper c.
  // Each thread makes its own share of the node rows in one sweep, keeping only the two rows of
  // g_T that its next node row needs (the row at the edge of two shares is made by both threads,
  // by the same expression): the same values as two passes over whole arrays of g_T, without them.
#pragma omp parallel
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    const int j0 = 1 + t * (ny - 1) / threads, j1 = 1 + (t + 1) * (ny - 1) / threads;  // this thread's node rows
    thread_local std::vector<double> buffer;
    buffer.resize(std::size_t(8) * nx);
    // g_T of triangle row r (between node rows r and r + 1), component c: lower at gl(r, c), upper at gu(r, c).
    auto gl = [&](int r, int c) { return &buffer[std::size_t((r % 2) * 4 + c) * nx]; };
    auto gu = [&](int r, int c) { return &buffer[std::size_t((r % 2) * 4 + 2 + c) * nx]; };
    auto triangles = [&](int r) {
      const std::size_t o = std::size_t(r) * nx;
      const double *vlx = &vl_[0][o], *vly = &vl_[1][o], *vux = &vu_[0][o], *vuy = &vu_[1][o];
      for (int c = 0; c < 2; ++c)
        detail::triangle_row(nx, inv_h, &(*f[c])[o], &(*f[c])[o + nx], vlx, vly, vux, vuy, gl(r, c), gu(r, c));
    };
    if (j0 < j1) {
      triangles(j0 - 1);
      for (int j = j0; j < j1; ++j) {
        triangles(j);
        for (int c = 0; c < 2; ++c)
          detail::gather_row(nx, inv_h, std::size_t(j) * nx, std::size_t(j - 1) * nx, gl(j, c), gu(j, c), gl(j - 1, c),
                             gu(j - 1, c), vl_[0].data(), vl_[1].data(), vu_[0].data(), vu_[1].data(),
                             &minv_a[c][std::size_t(j) * nx], minv_c ? &minv_c[c][std::size_t(j) * nx] : nullptr);
      }
    }
  }
}

void WaveLikeAdvection::advect(const VelocityField& V, VelocityField& u, double dt, int substeps) {
  const int nx = m_.nx, ny = m_.ny;
  // Freeze V at the triangle centroids (a copy, so that u may alias V).
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j)
    for (int c = 0; c < 2; ++c) {
      const std::vector<double>& v = (c == 0) ? V.u1 : V.u2;
      const double* a = &v[std::size_t(j) * nx];
      const double* b = &v[std::size_t(j + 1) * nx];
      double* L = &vl_[c][std::size_t(j) * nx];
      double* U = &vu_[c][std::size_t(j) * nx];
      auto centroid = [=](int i, int ip) {
        L[i] = (a[i] + a[ip] + b[i]) / 3.0;
        U[i] = (a[ip] + b[ip] + b[i]) / 3.0;
      };
      for (int i = 0; i + 1 < nx; ++i) centroid(i, i + 1);  // the last column wraps, apart
      centroid(nx - 1, 0);
    }
  const double tau = dt / substeps;
  const std::size_t first = std::size_t(nx), last = std::size_t(ny) * nx;  // interior nodes [first, last)
  std::vector<double>* f[2] = {&u.u1, &u.u2};
  // Taylor start: u¹ = u⁰ + τ u̇⁰ − τ²/2 M⁻¹A u⁰ (wall rows keep their values). With a single
  // substep (the usual case) we update u in place and skip the leapfrog history.
  if (substeps == 1) {
    apply(f, acc_, vel_);
    for (int c = 0; c < 2; ++c) {
      double* x = f[c]->data();
#pragma omp parallel for schedule(static)
      for (std::size_t n = first; n < last; ++n) x[n] += tau * vel_[c][n] - 0.5 * tau * tau * acc_[c][n];
    }
    return;
  }
  // (The interior loops below run in parallel, each node on its own: the same values whatever the
  // threads; the wall rows keep their values.)
  const std::ptrdiff_t begin = std::ptrdiff_t(first), end = std::ptrdiff_t(last);
  for (int c = 0; c < 2; ++c) prev_[c] = *f[c];
  std::vector<double>* const prev[2] = {&prev_[0], &prev_[1]};
  std::vector<double>* const cur[2] = {&cur_[0], &cur_[1]};
  apply(prev, acc_, vel_);
  for (int c = 0; c < 2; ++c) {
    const double *p = prev_[c].data(), *v = vel_[c].data(), *a = acc_[c].data();
    double* x = cur_[c].data();
    std::copy(p, p + begin, x);
    std::copy(p + end, p + prev_[c].size(), x + end);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t n = begin; n < end; ++n) x[n] = p[n] + tau * v[n] - 0.5 * tau * tau * a[n];
  }
  // Centred steps: u^{q+1} = 2u^q − u^{q−1} − τ² M⁻¹A u^q.
  for (int q = 1; q < substeps; ++q) {
    apply(cur, acc_, nullptr);
    for (int c = 0; c < 2; ++c) {
      const double *p = prev_[c].data(), *x = cur_[c].data(), *a = acc_[c].data();
      double* y = next_[c].data();
      std::copy(x, x + begin, y);
      std::copy(x + end, x + cur_[c].size(), y + end);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t n = begin; n < end; ++n) y[n] = 2.0 * x[n] - p[n] - tau * tau * a[n];
      std::swap(prev_[c], cur_[c]);
      std::swap(cur_[c], next_[c]);
    }
  }
  for (int c = 0; c < 2; ++c) std::swap(*f[c], cur_[c]);
}

}  // namespace rbc
