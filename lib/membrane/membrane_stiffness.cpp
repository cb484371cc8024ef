#include "membrane/membrane_stiffness.hpp"

#include <algorithm>
#include <vector>

namespace rbc {

Eigen::VectorXd MembraneStiffness::apply(const Eigen::VectorXd& v) const {
  Eigen::VectorXd out = band * v;
  if (area_gradient.size()) out += (area_coefficient * area_gradient.dot(v)) * area_gradient;
  return out;
}

Eigen::MatrixXd MembraneStiffness::right_multiply(const Eigen::MatrixXd& M) const {
  Eigen::MatrixXd out = M * band;
  if (area_gradient.size()) out.noalias() += (area_coefficient * (M * area_gradient)) * area_gradient.transpose();
  return out;
}

Eigen::MatrixXd MembraneStiffness::dense() const {
  Eigen::MatrixXd K = Eigen::MatrixXd(band);
  if (area_gradient.size()) K.noalias() += area_coefficient * area_gradient * area_gradient.transpose();
  return K;
}

MembraneStiffness membrane_stiffness(const MembraneModel& m, const Points& r, double target_area) {
  const int n = int(r.size());
  const double l0 = m.rest_length();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(std::size_t(n) * 4 * 13);
  auto block = [&](int a, int b, const Eigen::Matrix2d& B) {
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) t.emplace_back(2 * a + p, 2 * b + q, B(p, q));
  };
  for (int i = 0; i < n; ++i) {
    const int ip = (i + 1) % n, im = (i + n - 1) % n;
    // Spring i (nodes i, i+1): B = ∂²E_l/∂d²; it enters as [B −B; −B B].
    const Eigen::Vector2d d = r[ip] - r[i];
    const double l = d.norm();
    const Eigen::Vector2d e = d / l;
    const Eigen::Matrix2d ee = e * e.transpose();
    const Eigen::Matrix2d B = (m.kl / (l0 * l0)) * ee +
                              (m.kl * std::max(0.0, l - l0) / (l0 * l0 * l)) * (Eigen::Matrix2d::Identity() - ee);
    block(i, i, B);
    block(ip, ip, B);
    block(i, ip, -B);
    block(ip, i, -B);
    // Bending at node i: g = ∂t/∂(r_{i−1}, r_i, r_{i+1}) (as in membrane_energy), K += k_b g gᵀ.
    const Eigen::Vector2d a = r[i] - r[im], b = r[ip] - r[i];
    const double la = a.norm(), lb = b.norm();
    const double c = a.x() * b.y() - a.y() * b.x();
    const double den = la * lb + a.dot(b);
    const Eigen::Vector2d dc_da(b.y(), -b.x()), dc_db(-a.y(), a.x());
    const Eigen::Vector2d dd_da = (lb / la) * a + b, dd_db = (la / lb) * b + a;
    const Eigen::Vector2d dt_da = (dc_da * den - c * dd_da) / (den * den);
    const Eigen::Vector2d dt_db = (dc_db * den - c * dd_db) / (den * den);
    const int idx[3] = {im, i, ip};
    const Eigen::Vector2d g[3] = {-dt_da, dt_da - dt_db, dt_db};
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) block(idx[p], idx[q], m.kb * g[p] * g[q].transpose());
  }
  MembraneStiffness K;
  K.band.resize(2 * n, 2 * n);
  K.band.setFromTriplets(t.begin(), t.end());  // duplicates are summed
  // Area penalty: rank one, ∂s/∂r_i = ½ (y_{i+1} − y_{i−1}, x_{i−1} − x_{i+1}).
  if (m.area_penalty && m.ks != 0.0) {
    K.area_gradient.resize(2 * n);
    for (int i = 0; i < n; ++i) {
      const auto& p = r[(i + 1) % n];
      const auto& q = r[(i + n - 1) % n];
      K.area_gradient[2 * i] = 0.5 * (p.y() - q.y());
      K.area_gradient[2 * i + 1] = 0.5 * (q.x() - p.x());
    }
    K.area_coefficient = m.ks / (target_area * target_area);
  }
  return K;
}

}  // namespace rbc
