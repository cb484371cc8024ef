#pragma once
// The inner kernel of StepMobility::phase_averaged_matrix (step_mobility.cpp), on its own so that
// a test can hold it to its stated arithmetic bit for bit (tests/test_semi_implicit.cpp).
#include <cmath>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace rbc::detail {

// One pair's common case in phase_averaged_matrix: the source's four rows q are consecutive
// slots of H at the two samples around z (h0, h1: sixteen floats each, 4 q + 2α + β), so
//
//   a_v += Σ_q (b0_q h0[4q + v] + b1_q h1[4q + v]),  b1_q = w_k f w_q,  b0_q = w_k w_q − b1_q
//
// (the linear interpolation in z folded into the weights), summed in single precision. The
// arithmetic is fixed, so that the blocks (and every run) do not depend on how the compiler
// schedules it: each term t_q = fma(b0_q, h0_q, b1_q h1_q) (b1_q h1_q rounded first; on a
// machine without fused multiply-adds both products rounded, then added), the sum
// (((0 + t_0) + t_1) + t_2) + t_3 in that order, then added to a in double. With AVX2 two rows q
// at a time in one 8-float register: the same operations lane by lane, so the same bits as the
// portable form.
inline void add_interpolated_pair(const float* h0, const float* h1, double wk, double f, const double* wl, double* a) {
#if defined(__AVX2__) && defined(__FMA__)
  const __m256d w = _mm256_loadu_pd(wl);
  const __m128 b1 = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_set1_pd(wk * f), w));
  const __m128 b0 = _mm_sub_ps(_mm256_cvtpd_ps(_mm256_mul_pd(_mm256_set1_pd(wk), w)), b1);
  const __m256i lo = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1), hi = _mm256_setr_epi32(2, 2, 2, 2, 3, 3, 3, 3);
  const __m256 B0 = _mm256_castps128_ps256(b0), B1 = _mm256_castps128_ps256(b1);
  // t_0 | t_1 and t_2 | t_3
  const __m256 t01 = _mm256_fmadd_ps(_mm256_permutevar8x32_ps(B0, lo), _mm256_loadu_ps(h0),
                                     _mm256_mul_ps(_mm256_permutevar8x32_ps(B1, lo), _mm256_loadu_ps(h1)));
  const __m256 t23 = _mm256_fmadd_ps(_mm256_permutevar8x32_ps(B0, hi), _mm256_loadu_ps(h0 + 8),
                                     _mm256_mul_ps(_mm256_permutevar8x32_ps(B1, hi), _mm256_loadu_ps(h1 + 8)));
  __m128 sum = _mm_add_ps(_mm_setzero_ps(), _mm256_castps256_ps128(t01));
  sum = _mm_add_ps(sum, _mm256_extractf128_ps(t01, 1));
  sum = _mm_add_ps(sum, _mm256_castps256_ps128(t23));
  sum = _mm_add_ps(sum, _mm256_extractf128_ps(t23, 1));
  _mm256_storeu_pd(a, _mm256_add_pd(_mm256_loadu_pd(a), _mm256_cvtps_pd(sum)));
#else
  float b0[4], b1[4];
  for (int q = 0; q < 4; ++q) {
    b1[q] = float(wk * f * wl[q]);
    b0[q] = float(wk * wl[q]) - b1[q];
  }
  float sum[4] = {0, 0, 0, 0};
  for (int q = 0; q < 4; ++q)
    for (int v = 0; v < 4; ++v) {
      const float product = b1[q] * h1[4 * q + v];
#ifdef __FMA__
      sum[v] = sum[v] + std::fma(b0[q], h0[4 * q + v], product);
#else
      const float first = b0[q] * h0[4 * q + v];
      sum[v] = sum[v] + (first + product);
#endif
    }
  for (int v = 0; v < 4; ++v) a[v] += sum[v];
#endif
}

}  // namespace rbc::detail
