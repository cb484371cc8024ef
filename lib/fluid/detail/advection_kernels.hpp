#pragma once
// The wave-like advection's two inner loops (fluid/wave_like_advection.cpp states their equations):
// the gradients g_T of a row of triangles, and the gather of a node row from the triangles around
// its nodes. Written for speed, apart from the method: restrict pointers, and AVX2 where the
// machine has it, summed in the same order and fused at the same places as the scalar loop, so that
// every run keeps its bits whichever path it takes.
#include <cmath>
#include <cstddef>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace rbc::detail {

// g_T of one row of squares (its lower and upper triangles), rows a (j) and b (j + 1) of f. The
// arrays do not overlap (restrict, kept by not inlining: the compiler then vectorises the loop
// without run-time alias checks, of which it would need more than it makes); the last column
// wraps, apart. Every value is the expression of the loop this replaced (same bits).
[[gnu::noinline]] inline void triangle_row(int nx, double inv_h, const double* __restrict a, const double* __restrict b,
                                           const double* __restrict vlx, const double* __restrict vly,
                                           const double* __restrict vux, const double* __restrict vuy,
                                           double* __restrict gl, double* __restrict gu) {
  auto triangle = [&](int i, int ip) {
    gl[i] = (vlx[i] * (a[ip] - a[i]) + vly[i] * (b[i] - a[i])) * inv_h;
    gu[i] = (vux[i] * (b[ip] - b[i]) + vuy[i] * (b[ip] - a[ip])) * inv_h;
  };
  for (int i = 0; i + 1 < nx; ++i) triangle(i, i + 1);
  triangle(nx - 1, 0);
}

// Node row j (offset o = j nx into the centroid velocities vlx, vly, vux, vuy; od = (j − 1) nx) of
// WaveLikeAdvection::apply's gather, from the triangle rows j (glj, guj) and j − 1 (gld, gud):
// A[i] = (M⁻¹ A f)_n and, if C is given, C[i] = (−M⁻¹ C f)_n.
inline void gather_row(int nx, double inv_h, std::size_t o, std::size_t od, const double* glj, const double* guj,
                       const double* gld, const double* gud, const double* vlx, const double* vly, const double* vux,
                       const double* vuy, double* A, double* C) {
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

}  // namespace rbc::detail
