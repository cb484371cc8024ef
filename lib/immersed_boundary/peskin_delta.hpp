#pragma once
// Peskin's 4-point discrete delta (the study's Eqs. (11)-(12)):
//
//   φ(r) = (3 − 2|r| + √(1 + 4|r| − 4r²)) / 8,      |r| ≤ 1
//   φ(r) = (5 − 2|r| − √(−7 + 12|r| − 4r²)) / 8,    1 ≤ |r| ≤ 2
//   φ(r) = 0 otherwise;        δ_h(z) = φ(z/h)/h,   D_h(x) = δ_h(x1) δ_h(x2).
//
// Its defining properties (tested): Σ_j φ(r − j) = 1, Σ_j (r − j) φ(r − j) = 0 and
// Σ_j φ(r − j)² = 3/8 for every shift r.
#include <cmath>

namespace rbc {

inline double peskin_phi(double r) {
  const double a = std::abs(r);
  if (a <= 1.0) return (3.0 - 2.0 * a + std::sqrt(1.0 + 4.0 * a - 4.0 * a * a)) / 8.0;
  if (a <= 2.0) return (5.0 - 2.0 * a - std::sqrt(std::max(0.0, -7.0 + 12.0 * a - 4.0 * a * a))) / 8.0;
  return 0.0;
}

// The four weights φ(x/h − j) for the nodes j = first .. first+3 around x (in units of h).
inline int peskin_weights(double x_over_h, double w[4]) {
  const int first = int(std::floor(x_over_h)) - 1;
  for (int k = 0; k < 4; ++k) w[k] = peskin_phi(x_over_h - (first + k));
  return first;
}

}  // namespace rbc
