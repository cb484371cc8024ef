#pragma once
// Scans over a whole grid field that the fictitious-domain solves make at every solve.
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace rbc {

// max |x_k| over n values: four running maxima, so that the loop is not one long chain of
// dependent comparisons (such scans, three per solve, were the obstacle constraint's largest
// cost in a perf profile of).
inline double max_abs(const double* x, std::size_t n) {
  double m[4] = {0, 0, 0, 0};
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4)
    for (int l = 0; l < 4; ++l) m[l] = std::max(m[l], std::abs(x[k + l]));
  for (; k < n; ++k) m[0] = std::max(m[0], std::abs(x[k]));
  return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
}

}  // namespace rbc
