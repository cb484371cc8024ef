#include "fictitious_domain/helmholtz_green.hpp"

#include <algorithm>
#include <chrono>

namespace rbc {

HelmholtzGreen::HelmholtzGreen(PeriodicBandedSolver& A) : nx_(A.nx()), rows_(A.rows()) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = std::size_t(nx_) * rows_;
  g_.assign(std::size_t(rows_) * n, 0.0);
  std::vector<double> e1(n), e2(n);
  // Two source rows per fast solve pair.
  for (int rp = 0; rp < rows_; rp += 2) {
    const int rq = std::min(rp + 1, rows_ - 1);
    std::fill(e1.begin(), e1.end(), 0.0);
    std::fill(e2.begin(), e2.end(), 0.0);
    e1[std::size_t(rp) * nx_] = 1.0;
    e2[std::size_t(rq) * nx_] = 1.0;
    A.solve_pair(e1.data(), e2.data(), &g_[std::size_t(rp) * n], &g_[std::size_t(rq) * n]);
  }
  setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace rbc
