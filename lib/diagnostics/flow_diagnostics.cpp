#include "diagnostics/flow_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fem/p1_operators.hpp"

namespace rbc {

namespace {

// Σ_i u1(x_i, y_j) for each row j = 0..M: rows in parallel (this runs every step), each summed in
// one order whatever the threads.
std::vector<double> row_sums(const ChannelMesh& m, const VelocityField& u) {
  std::vector<double> row(std::size_t(m.ny) + 1, 0.0);
#pragma omp parallel for schedule(static) if (m.nx * m.ny >= 4096)
  for (int j = 0; j <= m.ny; ++j) {
    const double* u1 = &u.u1[std::size_t(j) * m.nx];  // row j (m.v(i, j) without the wrap)
    double r = 0;
    for (int i = 0; i < m.nx; ++i) r += u1[i];
    row[j] = r;
  }
  return row;
}

}  // namespace

MeanVelocities mean_velocities(const ChannelMesh& m, const VelocityField& u) {
  const std::vector<double> row = row_sums(m, u);
  double p1 = 0, nodal = 0;
  for (int j = 0; j <= m.ny; ++j) {
    p1 += lumped_mass(m, j) * row[j];
    nodal += row[j];
  }
  return {p1 / (m.length * m.height), nodal / (double(m.nx) * (m.ny + 1))};
}

double mean_velocity(const ChannelMesh& m, const VelocityField& u) { return mean_velocities(m, u).p1; }

double reynolds_number(double mean_velocity, const FluidProperties& f, double height) {
  return f.density * mean_velocity * height / f.viscosity;
}

double max_speed(const VelocityField& u) {
  // The largest |u|² first, one square root at the end (this runs every step; a maximum is exact
  // in any order, so threads may share it).
  const long size = long(u.u1.size());
  double m2 = 0;
#pragma omp parallel for schedule(static) reduction(max : m2) if (size >= 8192)
  for (long n = 0; n < size; ++n) m2 = std::max(m2, u.u1[n] * u.u1[n] + u.u2[n] * u.u2[n]);
  return std::sqrt(m2);
}

bool all_finite(const VelocityField& u) {
  const long size = long(u.u1.size());
  bool finite = true;
#pragma omp parallel for schedule(static) reduction(&& : finite) if (size >= 8192)
  for (long n = 0; n < size; ++n) finite = finite && std::isfinite(u.u1[n]) && std::isfinite(u.u2[n]);
  return finite;
}

}  // namespace rbc

namespace rbc {

PlasmaVelocity plasma_velocity(const ChannelMesh& m, const VelocityField& u, const std::vector<const Points*>& membranes) {
  // ∫_c^d u1 dy on column i, u1 linear between the nodes y_j = j h.
  auto integral = [&](int i, double c, double d) {
    double s = 0;
    const int j0 = std::max(0, int(std::floor(c / m.h))), j1 = std::min(m.ny - 1, int(std::floor(d / m.h)));
    for (int j = j0; j <= j1; ++j) {
      const double a = std::max(c, j * m.h), b = std::min(d, (j + 1) * m.h);
      if (b <= a) continue;
      const double ua = u.u1[m.v(i, j)], ub = u.u1[m.v(i, j + 1)];
      auto at = [&](double y) { return ua + (ub - ua) * (y - j * m.h) / m.h; };
      s += (b - a) * 0.5 * (at(a) + at(b));
    }
    return s;
  };
  PlasmaVelocity out;
  double flux_sum = 0, open_sum = 0;
  std::vector<double> ys;
  std::vector<std::pair<double, double>> extent;  // each cell's x1-range, found once
  for (const Points* r : membranes) {
    double xmin = INFINITY, xmax = -INFINITY;
    for (const auto& p : *r) { xmin = std::min(xmin, p.x()); xmax = std::max(xmax, p.x()); }
    extent.push_back({xmin, xmax});
  }
  for (int i = 0; i < m.nx; ++i) {
    double q = integral(i, 0.0, m.height), open = m.height;
    for (std::size_t c = 0; c < membranes.size(); ++c) {
      const Points* r = membranes[c];
      const auto [xmin, xmax] = extent[c];
      // The section x_i + k L for every period k that meets the cell.
      for (double X = m.x(i) + std::ceil((xmin - m.x(i)) / m.length) * m.length; X <= xmax; X += m.length) {
        ys.clear();
        for (std::size_t k = 0; k < r->size(); ++k) {
          const auto& a = (*r)[k];
          const auto& b = (*r)[(k + 1) % r->size()];
          if ((a.x() <= X) != (b.x() <= X)) ys.push_back(a.y() + (X - a.x()) * (b.y() - a.y()) / (b.x() - a.x()));
        }
        std::sort(ys.begin(), ys.end());
        for (std::size_t k = 0; k + 1 < ys.size(); k += 2) {
          q -= integral(i, ys[k], ys[k + 1]);
          open -= ys[k + 1] - ys[k];
        }
      }
    }
    flux_sum += q;
    open_sum += q / open;
  }
  out.flux_per_height = flux_sum / (m.nx * m.height);
  out.over_open_height = open_sum / m.nx;
  return out;
}

}  // namespace rbc
