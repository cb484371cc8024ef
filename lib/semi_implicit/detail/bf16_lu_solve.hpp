#pragma once
// The preconditioner's sweep for one cell (SemiImplicitMembraneStep::precondition): x = B⁻¹ v
// from the single-precision factors P B = L U, stored in bfloat16, on its own so that a test can
// hold it to its stated arithmetic bit for bit (tests/test_semi_implicit.cpp).
//
//   L y = P v (unit diagonal):  y_i = y_i − L_ij y_j  for j = 0, 1, …, i − 1 in that order,
//   U x = y:                    x_j = y_j · (1/U_jj), then
//                               x_i = x_i − U_ij x_j  for j = m − 1, …, i + 1 in that order,
//
// each update one fused multiply-add, fma(−L_ij, y_j, y_i), rounded once in single precision (on
// a machine without fused multiply-adds the product rounded, then subtracted).
//
// Column by column (each solved value taken out of the rest at once) the work comes as short
// loops of varying length, and x goes through memory at every column. With AVX2 the columns are
// taken eight at a time (a panel): the 8 × 8 triangle on the diagonal with the panel's values in
// registers, then the rows below it (above it, going back) eight rows to a register, each row
// taking the panel's eight updates in the order above. Every row sees the same operations in the
// same order, so the same bits as column by column. The factors are stored in the order this
// sweep reads them (pack_lu_bf16), one stream from start to end for each of the two solves: the
// blocks of 100 cells (4.6 MB) do not stay in cache between the sweeps, and a stream is what the
// hardware fetches ahead best.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace rbc::detail {

// bfloat16: the upper half of a float's bits (8 significant bits).
inline float from_bf16(std::uint16_t h) {
  const std::uint32_t u = std::uint32_t(h) << 16;
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

inline std::uint16_t to_bf16(float f) {  // rounded to nearest, ties to even
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  u += 0x7fffu + ((u >> 16) & 1u);
  return std::uint16_t(u >> 16);
}

// y − a b, the sweeps' one operation (see above).
inline float subtract_product(float y, float a, float b) {
#ifdef __FMA__
  return std::fma(-a, b, y);
#else
  return y - a * b;
#endif
}

// Column by column from the factors by columns (lu[j m + i] = LU_ij): the stated order itself
// (each column's updates independent of one another, so the compiler may vectorise them).
inline void lu_solve_bf16_by_columns(const std::uint16_t* lu, const float* inverse_diagonal, int m, float* x) {
  for (int j = 0; j < m; ++j) {
    const std::uint16_t* col = lu + std::size_t(j) * m;
    const float xj = x[j];
#pragma omp simd
    for (int i = j + 1; i < m; ++i) x[i] = subtract_product(x[i], from_bf16(col[i]), xj);
  }
  for (int j = m - 1; j >= 0; --j) {
    const std::uint16_t* col = lu + std::size_t(j) * m;
    const float xj = x[j] *= inverse_diagonal[j];
#pragma omp simd
    for (int i = 0; i < j; ++i) x[i] = subtract_product(x[i], from_bf16(col[i]), xj);
  }
}

namespace bf16_lu {
constexpr int kPanel = 8;  // columns per panel, rows per register

// The order the panel sweep reads the factors in, as (row, column) of LU: calls put(i, j) for
// every entry below the diagonal (forward) and then above it (backward), each once.
template <class Put>
void panel_order(int m, Put put) {
  for (int J = 0; J < m; J += kPanel) {  // L, panels left to right
    const int w = m - J < kPanel ? m - J : kPanel;
    for (int j = 0; j < w; ++j)  // the triangle, column by column
      for (int i = j + 1; i < w; ++i) put(J + i, J + j);
    int i = J + w;
    if (w == kPanel)
      for (; i + kPanel <= m; i += kPanel)  // eight rows at a time, column by column
        for (int k = 0; k < kPanel; ++k)
          for (int r = 0; r < kPanel; ++r) put(i + r, J + k);
    for (; i < m; ++i)  // the rest row by row
      for (int k = 0; k < w; ++k) put(i, J + k);
  }
  for (int end = m; end > 0; end -= kPanel) {  // U, panels right to left, columns right to left
    const int J = end - kPanel > 0 ? end - kPanel : 0, w = end - J;
    for (int j = w - 1; j >= 0; --j)
      for (int i = 0; i < j; ++i) put(J + i, J + j);
    int i = 0;
    if (w == kPanel)
      for (; i + kPanel <= J; i += kPanel)
        for (int k = 0; k < kPanel; ++k)
          for (int r = 0; r < kPanel; ++r) put(i + r, end - 1 - k);
    for (; i < J; ++i)
      for (int k = 0; k < w; ++k) put(i, end - 1 - k);
  }
}
}  // namespace bf16_lu

// The factors by columns (lu[j m + i] = LU_ij, single precision) in bfloat16, in the order
// lu_solve_bf16 reads them (with AVX2 the panels' order, otherwise by columns).
inline void pack_lu_bf16(const float* lu, int m, std::vector<std::uint16_t>& out) {
  out.clear();
  out.reserve(std::size_t(m) * m);
#if defined(__AVX2__) && defined(__FMA__)
  bf16_lu::panel_order(m, [&](int i, int j) { out.push_back(to_bf16(lu[std::size_t(j) * m + i])); });
#else
  for (std::size_t k = 0; k < std::size_t(m) * m; ++k) out.push_back(to_bf16(lu[k]));
#endif
}

#if defined(__AVX2__) && defined(__FMA__)
namespace bf16_lu {
inline __m256 load8(const std::uint16_t* p) {  // eight bfloat16 to eight floats
  const __m256i w = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
  return _mm256_castsi256_ps(_mm256_slli_epi32(w, 16));
}

// Rows [begin, end) take the updates of the columns whose solved values are c[0..count), in
// that order, their coefficients read from s (as panel_order puts them); returns s past them.
inline const std::uint16_t* panel_rows(const std::uint16_t* s, const float* c, int count, int begin, int end, float* x) {
  int i = begin;
  if (count == kPanel) {
    __m256 b[kPanel];
    for (int k = 0; k < kPanel; ++k) b[k] = _mm256_set1_ps(c[k]);
    for (; i + 2 * kPanel <= end; i += 2 * kPanel, s += 2 * kPanel * kPanel) {  // two chains in flight
      __m256 r0 = _mm256_loadu_ps(x + i), r1 = _mm256_loadu_ps(x + i + kPanel);
      for (int k = 0; k < kPanel; ++k) {
        r0 = _mm256_fnmadd_ps(load8(s + kPanel * k), b[k], r0);
        r1 = _mm256_fnmadd_ps(load8(s + kPanel * (kPanel + k)), b[k], r1);
      }
      _mm256_storeu_ps(x + i, r0);
      _mm256_storeu_ps(x + i + kPanel, r1);
    }
    for (; i + kPanel <= end; i += kPanel, s += kPanel * kPanel) {
      __m256 r = _mm256_loadu_ps(x + i);
      for (int k = 0; k < kPanel; ++k) r = _mm256_fnmadd_ps(load8(s + kPanel * k), b[k], r);
      _mm256_storeu_ps(x + i, r);
    }
  }
  for (; i < end; ++i) {
    float r = x[i];
    for (int k = 0; k < count; ++k) r = subtract_product(r, from_bf16(*s++), c[k]);
    x[i] = r;
  }
  return s;
}
}  // namespace bf16_lu
#endif

// x ← B⁻¹ x (x holds P v on entry); lu from pack_lu_bf16.
inline void lu_solve_bf16(const std::uint16_t* lu, const float* inverse_diagonal, int m, float* x) {
#if defined(__AVX2__) && defined(__FMA__)
  using bf16_lu::kPanel;
  const std::uint16_t* s = lu;
  float y[kPanel];  // a panel's values, in registers through the triangle
  for (int J = 0; J < m; J += kPanel) {  // L y = P v, panels left to right
    const int w = m - J < kPanel ? m - J : kPanel;
    for (int k = 0; k < w; ++k) y[k] = x[J + k];
    if (w == kPanel) {
#pragma GCC unroll 8
      for (int j = 0; j < kPanel; ++j)
#pragma GCC unroll 8
        for (int i = j + 1; i < kPanel; ++i) y[i] = subtract_product(y[i], from_bf16(s[j * (2 * kPanel - j - 1) / 2 + i - j - 1]), y[j]);
      s += kPanel * (kPanel - 1) / 2;
    } else {
      for (int j = 0; j < w; ++j)
        for (int i = j + 1; i < w; ++i) y[i] = subtract_product(y[i], from_bf16(*s++), y[j]);
    }
    for (int k = 0; k < w; ++k) x[J + k] = y[k];
    s = bf16_lu::panel_rows(s, y, w, J + w, m, x);
  }
  for (int end = m; end > 0; end -= kPanel) {  // U x = y, panels right to left
    const int J = end - kPanel > 0 ? end - kPanel : 0, w = end - J;
    for (int k = 0; k < w; ++k) y[k] = x[J + k];
    if (w == kPanel) {
      // Column j's i < j, columns from the right: column j starts after the columns j + 1.. of
      // the panel, whose lengths are j + 1, …, kPanel − 1.
#pragma GCC unroll 8
      for (int j = kPanel - 1; j >= 0; --j) {
        y[j] *= inverse_diagonal[J + j];
#pragma GCC unroll 8
        for (int i = 0; i < j; ++i)
          y[i] = subtract_product(y[i], from_bf16(s[(kPanel - 1 - j) * (kPanel + j) / 2 + i]), y[j]);
      }
      s += kPanel * (kPanel - 1) / 2;
    } else {
      for (int j = w - 1; j >= 0; --j) {
        y[j] *= inverse_diagonal[J + j];
        for (int i = 0; i < j; ++i) y[i] = subtract_product(y[i], from_bf16(*s++), y[j]);
      }
    }
    for (int k = 0; k < w; ++k) x[J + k] = y[k];
    float c[kPanel];  // the panel's solved values, right to left
    for (int k = 0; k < w; ++k) c[k] = y[w - 1 - k];
    s = bf16_lu::panel_rows(s, c, w, 0, J, x);
  }
#else
  lu_solve_bf16_by_columns(lu, inverse_diagonal, m, x);
#endif
}

}  // namespace rbc::detail
