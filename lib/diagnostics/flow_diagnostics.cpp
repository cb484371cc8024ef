#include "diagnostics/flow_diagnostics.hpp"

#include <algorithm>
#include <cmath>

#include "fem/p1_operators.hpp"

namespace rbc {

double mean_velocity(const ChannelMesh& m, const VelocityField& u) {
  double s = 0;
  for (int j = 0; j <= m.ny; ++j) {
    double row = 0;
    for (int i = 0; i < m.nx; ++i) row += u.u1[m.v(i, j)];
    s += lumped_mass(m, j) * row;
  }
  return s / (m.length * m.height);
}

double reynolds_number(double mean_velocity, const FluidProperties& f, double height) {
  return f.density * mean_velocity * height / f.viscosity;
}

double max_speed(const VelocityField& u) {
  // The largest |u|² first, one square root at the end (this runs every step).
  double m2 = 0;
  for (std::size_t n = 0; n < u.u1.size(); ++n) m2 = std::max(m2, u.u1[n] * u.u1[n] + u.u2[n] * u.u2[n]);
  return std::sqrt(m2);
}

bool all_finite(const VelocityField& u) {
  for (std::size_t n = 0; n < u.u1.size(); ++n)
    if (!std::isfinite(u.u1[n]) || !std::isfinite(u.u2[n])) return false;
  return true;
}

}  // namespace rbc
