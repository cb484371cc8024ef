#include "membrane/spring_membrane.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rbc {

double MembraneConstants::stiffness_scale() const {
  if (units == "si") return 1.0;
  if (units == "cgs") return 100.0;
  throw std::invalid_argument("membrane units must be \"si\" or \"cgs\", not \"" + units + "\"");
}

double MembraneModel::rest_length() const { return 2.0 * std::numbers::pi * radius / nodes; }

MembraneModel MembraneModel::from(const MembraneConstants& c, int nodes, double radius, bool area_penalty) {
  const double s = c.stiffness_scale();
  return {nodes, radius, c.kl * s, c.kb * s, c.ks * s, area_penalty};
}

double enclosed_area(const Points& r) {
  double s = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const auto& p = r[i];
    const auto& q = r[(i + 1) % n];
    s += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * s;
}

double perimeter(const Points& r) {
  double l = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) l += (r[(i + 1) % n] - r[i]).norm();
  return l;
}

Eigen::Vector2d area_centroid(const Points& r) {
  // Centroid of the polygon: (1/(6s)) Σ (r_i + r_{i+1}) (r_i × r_{i+1}), taken relative to r_0
  // so that large coordinates do not cost digits.
  const Eigen::Vector2d o = r[0];
  double s = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const Eigen::Vector2d p = r[i] - o, q = r[(i + 1) % n] - o;
    const double w = p.x() * q.y() - q.x() * p.y();
    s += w;
    c += (p + q) * w;
  }
  return o + c / (3.0 * s);
}

double max_strain(const Points& r, double l0) {
  double m = 0;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) m = std::max(m, std::abs((r[(i + 1) % n] - r[i]).norm() - l0) / l0);
  return m;
}

MembraneEnergy membrane_energy(const MembraneModel& m, const Points& r, double target_area, Points* forces) {
  const std::size_t n = r.size();
  const double l0 = m.rest_length();
  MembraneEnergy e;
  if (forces) forces->assign(n, Eigen::Vector2d::Zero());
  auto add = [&](std::size_t i, const Eigen::Vector2d& grad) {
    if (forces) (*forces)[i] -= grad;  // F = −∂E/∂r
  };
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t ip = (i + 1) % n, im = (i + n - 1) % n;
    // (5) Spring i, from node i to node i+1: ∂E/∂r_{i+1} = k_l (l − l0)/l0² · e.
    const Eigen::Vector2d d = r[ip] - r[i];
    const double l = d.norm();
    const double strain = (l - l0) / l0;
    e.stretching += 0.5 * m.kl * strain * strain;
    const Eigen::Vector2d gs = (m.kl * strain / l0) * (d / l);
    add(ip, gs);
    add(i, -gs);
    // (6) Bending at node i: t = tan(θ/2) = c/d with c = a × b, d = |a||b| + a·b.
    const Eigen::Vector2d a = r[i] - r[im], b = r[ip] - r[i];
    const double la = a.norm(), lb = b.norm();
    const double c = a.x() * b.y() - a.y() * b.x();
    const double den = la * lb + a.dot(b);
    const double t = c / den;
    e.bending += 0.5 * m.kb * t * t;
    // ∂t/∂a = (∂c/∂a d − c ∂d/∂a)/d², ∂c/∂a = (b_y, −b_x), ∂d/∂a = (|b|/|a|) a + b; same for b.
    const Eigen::Vector2d dc_da(b.y(), -b.x()), dc_db(-a.y(), a.x());
    const Eigen::Vector2d dd_da = (lb / la) * a + b, dd_db = (la / lb) * b + a;
    const Eigen::Vector2d dt_da = (dc_da * den - c * dd_da) / (den * den);
    const Eigen::Vector2d dt_db = (dc_db * den - c * dd_db) / (den * den);
    const Eigen::Vector2d ga = m.kb * t * dt_da, gb = m.kb * t * dt_db;
    add(im, -ga);
    add(i, ga - gb);
    add(ip, gb);
  }
  // (7) Area penalty: ∂s/∂r_i = ½ (y_{i+1} − y_{i−1}, x_{i−1} − x_{i+1}).
  if (m.area_penalty && m.ks != 0.0) {
    const double s = enclosed_area(r);
    const double ds = (s - target_area) / target_area;
    e.area = 0.5 * m.ks * ds * ds;
    const double coef = m.ks * ds / target_area;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = r[(i + 1) % n];
      const auto& q = r[(i + n - 1) % n];
      add(i, coef * 0.5 * Eigen::Vector2d(p.y() - q.y(), q.x() - p.x()));
    }
  }
  return e;
}

}  // namespace rbc
