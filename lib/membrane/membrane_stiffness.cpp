#include "membrane/membrane_stiffness.hpp"

#include <algorithm>
#include <vector>

namespace rbc {

namespace {
// The five nodes a node's band row couples to, as (node, offset), in increasing node order (the
// order a column-major sparse matrix sums them in).
struct Neighbour { int node, offset; };
void neighbours(int i, int n, Neighbour out[5]) {
  int k = 0;
  for (int o = -2; o <= 2; ++o) out[k++] = {(i + o + n) % n, o};
  if (i >= 2 && i + 2 < n) return;  // no wrap: already in order
  std::sort(out, out + 5, [](const Neighbour& a, const Neighbour& b) { return a.node < b.node; });
}
}  // namespace

Eigen::VectorXd MembraneStiffness::apply(const Eigen::VectorXd& v) const {
  const int n = int(band.size() / 5);
  Eigen::VectorXd out(2 * n);
  Neighbour nb[5];
  for (int i = 0; i < n; ++i) {
    neighbours(i, n, nb);
    for (int p = 0; p < 2; ++p) {
      double sum = 0;
      for (const Neighbour& m : nb)
        for (int q = 0; q < 2; ++q) sum += band[5 * i + m.offset + 2](p, q) * v[2 * m.node + q];
      out[2 * i + p] = sum;
    }
  }
  if (area_gradient.size()) out += (area_coefficient * area_gradient.dot(v)) * area_gradient;
  return out;
}

Eigen::MatrixXd MembraneStiffness::right_multiply(const Eigen::MatrixXd& M) const {
  // (M K)(:, 2j + q) = Σ_m Σ_p M(:, 2m + p) K(2m + p, 2j + q) over the rows m of column node j.
  const int n = int(band.size() / 5);
  Eigen::MatrixXd out(M.rows(), 2 * n);
  Neighbour nb[5];
  for (int j = 0; j < n; ++j) {
    neighbours(j, n, nb);  // the band is symmetric in its pattern: rows of column j = nodes j + o
    for (int q = 0; q < 2; ++q) {
      auto col = out.col(2 * j + q);
      col.setZero();
      for (const Neighbour& m : nb)
        for (int p = 0; p < 2; ++p) col += band[5 * m.node - m.offset + 2](p, q) * M.col(2 * m.node + p);
    }
  }
  if (area_gradient.size()) out.noalias() += (area_coefficient * (M * area_gradient)) * area_gradient.transpose();
  return out;
}

Eigen::MatrixXd MembraneStiffness::dense() const {
  const int n = int(band.size() / 5);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i)
    for (int o = -2; o <= 2; ++o) K.block<2, 2>(2 * i, 2 * ((i + o + n) % n)) = band[5 * i + o + 2];
  if (area_gradient.size()) K.noalias() += area_coefficient * area_gradient * area_gradient.transpose();
  return K;
}

MembraneStiffness membrane_stiffness(const MembraneModel& m, const Points& r, double target_area) {
  const int n = int(r.size());
  const double l0 = m.rest_length();
  MembraneStiffness K;
  K.band.assign(std::size_t(5) * n, Eigen::Matrix2d::Zero());
  auto block = [&](int a, int b, const Eigen::Matrix2d& B) {  // K(a, b) += B
    int o = (b - a + n) % n;
    o = o > 2 ? o - n : o;
    K.band[std::size_t(5) * a + o + 2] += B;
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
