#include "fluid/wave_like_advection.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <omp.h>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace rbc {

namespace {
// g_T of one row of squares (its lower and upper triangles), rows a (j) and b (j + 1) of f. The
// arrays do not overlap (restrict, kept by not inlining: the compiler then vectorises the loop
// without run-time alias checks, of which it would need more than it makes); the last column
// wraps, apart. Every value is the expression of the loop this replaced (same bits).
[[gnu::noinline]] void triangle_row(int nx, double inv_h, const double* __restrict a, const double* __restrict b,
                                    const double* __restrict vlx, const double* __restrict vly,
                                    const double* __restrict vux, const double* __restrict vuy, double* __restrict gl,
                                    double* __restrict gu) {
  auto triangle = [&](int i, int ip) {
    gl[i] = (vlx[i] * (a[ip] - a[i]) + vly[i] * (b[i] - a[i])) * inv_h;
    gu[i] = (vux[i] * (b[ip] - b[i]) + vuy[i] * (b[ip] - a[ip])) * inv_h;
  };
  for (int i = 0; i + 1 < nx; ++i) triangle(i, i + 1);
  triangle(nx - 1, 0);
}
}  // namespace

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
        triangle_row(nx, inv_h, &(*f[c])[o], &(*f[c])[o + nx], vlx, vly, vux, vuy, gl(r, c), gu(r, c));
    };
    if (j0 < j1) {
      triangles(j0 - 1);
      for (int j = j0; j < j1; ++j) {
        triangles(j);
        for (int c = 0; c < 2; ++c)
          gather_row(nx, inv_h, j, gl(j, c), gu(j, c), gl(j - 1, c), gu(j - 1, c), &minv_a[c][std::size_t(j) * nx],
                     minv_c ? &minv_c[c][std::size_t(j) * nx] : nullptr);
      }
    }
  }
}

void WaveLikeAdvection::gather_row(int nx, double inv_h, int j, const double* glj, const double* guj, const double* gld,
                                   const double* gud, double* A, double* C) const {
  const std::size_t o = std::size_t(j) * nx, od = std::size_t(j - 1) * nx;
  const double *vlx = &vl_[0][0], *vly = &vl_[1][0], *vux = &vu_[0][0], *vuy = &vu_[1][0];
#if defined(__AVX2__) && defined(__FMA__)
  // The sums of the scalar loop below in the order, and fused into multiply-adds where, the
  // compiler fused them for x86-64-v3 (read off its code), written out: four nodes at a time in
  // AVX2 registers and the wrapping first node and the remainder one at a time, the same
  // operations in both, so that every run keeps its bits. (Left to the compiler, the vectorised
  // loop fused differently and every run's bits changed; measured.)
  auto node = [&](int i, int im) {
    const std::size_t a = o + i, b = o + im, cc = od + i, d = od + im;
    double s = std::fma(glj[i], -vlx[a] - vly[a], glj[im] * vlx[b]);
    s = std::fma(gld[i], vly[cc], s);
    s = std::fma(-guj[im], vuy[b], s);
    s = std::fma(gud[im], vux[d] + vuy[d], s);
    s = std::fma(-gud[i], vux[cc], s);
    A[i] = 0.5 * s * inv_h;  // |T|/M = 1/2, one more 1/h from ∇φ
    if (C) C[i] = -(glj[i] + glj[im] + gld[i] + guj[im] + gud[im] + gud[i]) / 6.0;
  };
  node(0, nx - 1);
  const __m256d half = _mm256_set1_pd(0.5), ih = _mm256_set1_pd(inv_h), six = _mm256_set1_pd(6.0), sign = _mm256_set1_pd(-0.0);
  int i = 1;
  for (; i + 4 <= nx; i += 4) {  // im = i − 1
    const __m256d gi = _mm256_loadu_pd(glj + i), gim = _mm256_loadu_pd(glj + i - 1), gdi = _mm256_loadu_pd(gld + i),
                  ujm = _mm256_loadu_pd(guj + i - 1), udm = _mm256_loadu_pd(gud + i - 1), udi = _mm256_loadu_pd(gud + i);
    const __m256d t = _mm256_sub_pd(_mm256_xor_pd(_mm256_loadu_pd(vlx + o + i), sign), _mm256_loadu_pd(vly + o + i));
    __m256d s = _mm256_fmadd_pd(gi, t, _mm256_mul_pd(gim, _mm256_loadu_pd(vlx + o + i - 1)));
    s = _mm256_fmadd_pd(gdi, _mm256_loadu_pd(vly + od + i), s);
    s = _mm256_fnmadd_pd(ujm, _mm256_loadu_pd(vuy + o + i - 1), s);
    s = _mm256_fmadd_pd(udm, _mm256_add_pd(_mm256_loadu_pd(vux + od + i - 1), _mm256_loadu_pd(vuy + od + i - 1)), s);
    s = _mm256_fnmadd_pd(udi, _mm256_loadu_pd(vux + od + i), s);
    _mm256_storeu_pd(A + i, _mm256_mul_pd(_mm256_mul_pd(half, s), ih));
    if (C) {
      const __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_add_pd(gi, gim), gdi), ujm), udm), udi);
      _mm256_storeu_pd(C + i, _mm256_div_pd(_mm256_xor_pd(sum, sign), six));
    }
  }
  for (; i < nx; ++i) node(i, i - 1);
#else
  for (int i = 0; i < nx; ++i) {
    const int im = (i == 0) ? nx - 1 : i - 1;
    const std::size_t a = o + i, b = o + im, cc = od + i, d = od + im;
    const double s = glj[i] * (-vlx[a] - vly[a]) + glj[im] * vlx[b] + gld[i] * vly[cc] - guj[im] * vuy[b] +
                     gud[im] * (vux[d] + vuy[d]) - gud[i] * vux[cc];
    A[i] = 0.5 * s * inv_h;  // |T|/M = 1/2, one more 1/h from ∇φ
    if (C) C[i] = -(glj[i] + glj[im] + gld[i] + guj[im] + gud[im] + gud[i]) / 6.0;
  }
#endif
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
