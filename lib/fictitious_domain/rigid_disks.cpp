#include "fictitious_domain/rigid_disks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fictitious_domain/field_scans.hpp"

namespace rbc {

namespace {

// The rigid motion's rows at a point x − G = o: component 0 (1, 0, −o2), component 1 (0, 1, o1).
Eigen::RowVector3d rigid_row(int component, const Eigen::Vector2d& o) {
  return component == 0 ? Eigen::RowVector3d(1.0, 0.0, -o.y()) : Eigen::RowVector3d(0.0, 1.0, o.x());
}

// u read at a point (a node or bilinear).
double read(const double* u, const DiskPoints::Point& p) {
  double s = 0;
  for (int a = 0; a < p.count; ++a) s += p.weights[std::size_t(a)] * u[p.nodes[std::size_t(a)]];
  return s;
}

}  // namespace

int boundary_point_count(double r, double h, double spacing) {
  const int n = std::max(8, int(std::ceil(2 * std::numbers::pi * r / (spacing * h))));
  return n + n % 2;
}

DiskPoints disk_points(const ChannelMesh& m, const Disk& disk, double boundary_spacing) {
  const double h = m.h, r = disk.radius, gx = disk.center.x(), gy = disk.center.y();
  if (gy - r < h || gy + r > m.height - h)
    throw std::invalid_argument("rigid disk at (" + std::to_string(gx * 1e6) + ", " + std::to_string(gy * 1e6) + ") um, radius " +
                                std::to_string(r * 1e6) + " um: closer than one mesh cell to a wall");
  auto index = [&](int i, int j) { return (j - 1) * m.nx + m.wrap(i); };
  DiskPoints d;
  // Nodes inside ω farther than h/2 from its boundary.
  std::vector<int> inside;
  std::vector<Eigen::Vector2d> inside_offset;
  const int i0 = int(std::ceil((gx - r) / h)), i1 = int(std::floor((gx + r) / h));
  const int j0 = std::max(1, int(std::ceil((gy - r) / h))), j1 = std::min(m.ny - 1, int(std::floor((gy + r) / h)));
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const Eigen::Vector2d o(i * h - gx, j * h - gy);
      if (o.norm() <= r - 0.5 * h) {
        inside.push_back(index(i, j));
        inside_offset.push_back(o);
      }
    }
  // Points on ∂ω about s h apart (s = boundary_spacing), bilinear.
  const int nb = boundary_point_count(r, h, boundary_spacing);
  std::vector<DiskPoints::Point> boundary;
  std::vector<int> stencil;
  for (int b = 0; b < nb; ++b) {
    const double t = 2 * std::numbers::pi * b / nb;
    const Eigen::Vector2d o(r * std::cos(t), r * std::sin(t));
    const double x = (gx + o.x()) / h, y = (gy + o.y()) / h;
    const int ia = int(std::floor(x)), ja = int(std::floor(y));
    const double fx = x - ia, fy = y - ja;
    DiskPoints::Point p;
    p.offset = o;
    p.count = 4;
    p.nodes = {index(ia, ja), index(ia + 1, ja), index(ia, ja + 1), index(ia + 1, ja + 1)};
    p.weights = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    for (int a = 0; a < 4; ++a)
      if (p.weights[std::size_t(a)] != 0.0) stencil.push_back(p.nodes[std::size_t(a)]);
    boundary.push_back(p);
  }
  std::vector<int> sorted_inside = inside;
  std::sort(sorted_inside.begin(), sorted_inside.end());
  std::sort(stencil.begin(), stencil.end());
  auto in = [](const std::vector<int>& v, int k) { return std::binary_search(v.begin(), v.end(), k); };
  for (std::size_t n = 0; n < inside.size(); ++n) {
    const int k = inside[n], j = k / m.nx + 1, i = k % m.nx;
    const bool deep = in(sorted_inside, index(i - 1, j)) && in(sorted_inside, index(i + 1, j)) && j > 1 &&
                      in(sorted_inside, index(i, j - 1)) && j < m.ny - 1 && in(sorted_inside, index(i, j + 1)) && !in(stencil, k);
    DiskPoints::Point p;
    p.offset = inside_offset[n];
    p.nodes[0] = k;
    p.weights[0] = 1.0;
    p.count = 1;
    (deep ? d.deep : d.ring).push_back(p);
  }
  d.interior_nodes = int(inside.size());
  d.ring.insert(d.ring.end(), boundary.begin(), boundary.end());
  return d;
}

DiskConstraint::DiskConstraint(const ChannelMesh& mesh, PeriodicBandedSolver& A, double rho, double dt, double tolerance,
                               int max_iterations, double boundary_spacing)
    : m_(mesh),
      A_(A),
      green_(A),
      c_(rho * mesh.h * mesh.h / dt),
      tolerance_(tolerance),
      max_iterations_(max_iterations),
      boundary_spacing_(boundary_spacing) {
  for (auto& r : rhs_) r.assign(std::size_t(A.nx()) * A.rows(), 0.0);
}

void DiskConstraint::set_disks(const std::vector<Disk>& disks) {
  disks_ = disks;
  points_.clear();
  factors_.clear();
  q_.assign(disks.size(), Eigen::Vector3d::Zero());
  for (const Disk& disk : disks) {
    const DiskPoints p = disk_points(m_, disk, boundary_spacing_);
    const int nr = int(p.ring.size()), nd = int(p.deep.size());
    Factors f;
    // Every point's nodes as (interior row, column), found once: the table is read for every pair
    // of points below, by row and column (HelmholtzGreen::at).
    using Nodes = std::array<std::array<int, 2>, 4>;
    auto rows_columns = [&](const DiskPoints::Point& pt) {
      Nodes rc{};
      for (int x = 0; x < pt.count; ++x) rc[std::size_t(x)] = {pt.nodes[std::size_t(x)] / m_.nx, pt.nodes[std::size_t(x)] % m_.nx};
      return rc;
    };
    std::vector<Nodes> ring(static_cast<std::size_t>(nr)), deep(static_cast<std::size_t>(nd));
    for (int a = 0; a < nr; ++a) ring[std::size_t(a)] = rows_columns(p.ring[std::size_t(a)]);
    for (int d = 0; d < nd; ++d) deep[std::size_t(d)] = rows_columns(p.deep[std::size_t(d)]);
    auto green = [&](const std::array<int, 2>& k, const std::array<int, 2>& kp) { return green_.at(k[0], k[1], kp[0], kp[1]); };
    // S_R = B_R A⁻¹ B_Rᵀ from the table.
    Eigen::MatrixXd S(nr, nr);
    for (int a = 0; a < nr; ++a)
      for (int b = a; b < nr; ++b) {
        double s = 0;
        for (int x = 0; x < p.ring[std::size_t(a)].count; ++x)
          for (int y = 0; y < p.ring[std::size_t(b)].count; ++y)
            s += p.ring[std::size_t(a)].weights[std::size_t(x)] * p.ring[std::size_t(b)].weights[std::size_t(y)] *
                 green(ring[std::size_t(a)][std::size_t(x)], ring[std::size_t(b)][std::size_t(y)]);
        S(a, b) = S(b, a) = s;
      }
    f.S.compute(S);
    if (f.S.info() != Eigen::Success) throw std::runtime_error("rigid disk: the capacitance matrix S_R is not positive definite");
    // M: the ring's response to the deep multipliers' rigid part c R_D q; K = M − R_R.
    Eigen::MatrixXd K[2] = {Eigen::MatrixXd::Zero(nr, 3), Eigen::MatrixXd::Zero(nr, 3)};
    for (int a = 0; a < nr; ++a) {
      const DiskPoints::Point& pa = p.ring[std::size_t(a)];
      // Row a of each K summed in registers, then stored (the sum of the strided row in place
      // waited on its own stores at every deep node).
      Eigen::RowVector3d row[2] = {Eigen::RowVector3d::Zero(), Eigen::RowVector3d::Zero()};
      for (int d = 0; d < nd; ++d) {
        double g = 0;
        for (int x = 0; x < pa.count; ++x) g += pa.weights[std::size_t(x)] * green(ring[std::size_t(a)][std::size_t(x)], deep[std::size_t(d)][0]);
        for (int comp = 0; comp < 2; ++comp) row[comp] += c_ * g * rigid_row(comp, p.deep[std::size_t(d)].offset);
      }
      for (int comp = 0; comp < 2; ++comp) K[comp].row(a) = row[comp];
      for (int comp = 0; comp < 2; ++comp) {
        if (f.Q[comp].rows() == 0) f.Q[comp] = Eigen::MatrixXd::Zero(nr, 3);
        f.Q[comp].row(a) = rigid_row(comp, pa.offset);
      }
    }
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    for (const auto& d : p.deep)
      for (int comp = 0; comp < 2; ++comp) N += rigid_row(comp, d.offset).transpose() * rigid_row(comp, d.offset);
    f.T = c_ * N;
    for (int comp = 0; comp < 2; ++comp) {
      K[comp] -= f.Q[comp];
      f.SinvK[comp] = f.S.solve(K[comp]);
      f.T -= f.Q[comp].transpose() * f.SinvK[comp];
    }
    f.Tlu.compute(f.T);
    points_.push_back(p);
    factors_.push_back(std::move(f));
  }
}

void DiskConstraint::solve_pair(double* b1, double* b2) {
  double* u[2] = {b1, b2};
  const std::size_t n = rhs_[0].size();
  const std::size_t nd = disks_.size();
  // Deep multipliers in closed form: λ_d = c (R q)_d − b_d; b_d leaves the right-hand side and its
  // moment R_dᵀ b_d is the force defect the disk's first solve must balance.
  std::vector<Eigen::Vector3d> force(nd, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < nd; ++k)
    for (const auto& d : points_[k].deep)
      for (int comp = 0; comp < 2; ++comp) {
        force[k] += rigid_row(comp, d.offset).transpose() * u[comp][d.nodes[0]];
        u[comp][d.nodes[0]] = 0.0;
      }
  A_.solve_pair(b1, b2, b1, b2);
  for (auto& q : q_) q.setZero();
  int it = 0;
  double residual = 0;
  for (;;) {
    // The defect at every collocation point, u − R q, and its largest value.
    const double scale = std::max({max_abs(b1, n), max_abs(b2, n), 1e-300});
    residual = 0;
    std::vector<Eigen::VectorXd> g(2 * nd);
    for (std::size_t k = 0; k < nd; ++k) {
      const DiskPoints& p = points_[k];
      for (int comp = 0; comp < 2; ++comp) {
        Eigen::VectorXd& gk = g[2 * k + std::size_t(comp)];
        gk.resize(Eigen::Index(p.ring.size()));
        for (std::size_t a = 0; a < p.ring.size(); ++a) {
          gk[Eigen::Index(a)] = read(u[comp], p.ring[a]) - rigid_row(comp, p.ring[a].offset).dot(q_[k]);
          residual = std::max(residual, std::abs(gk[Eigen::Index(a)]));
        }
        for (const auto& d : p.deep) residual = std::max(residual, std::abs(u[comp][d.nodes[0]] - rigid_row(comp, d.offset).dot(q_[k])));
      }
    }
    residual /= scale;
    if (it > 0 && residual <= tolerance_) break;
    if (it == max_iterations_)
      throw std::runtime_error("rigid disks: step 4 did not converge in " + std::to_string(max_iterations_) + " iterations (velocity defect " +
                               std::to_string(residual) + " of the field's scale)");
    ++it;
    // Each disk's system against the current field; the corrections' right-hand sides.
    for (std::size_t k = 0; k < nd; ++k) {
      const DiskPoints& p = points_[k];
      const Factors& f = factors_[k];
      Eigen::VectorXd Sg[2];
      Eigen::Vector3d rhs = it == 1 ? force[k] : Eigen::Vector3d::Zero();
      for (int comp = 0; comp < 2; ++comp) {
        Sg[comp] = f.S.solve(g[2 * k + std::size_t(comp)]);
        rhs += f.Q[comp].transpose() * Sg[comp];
      }
      const Eigen::Vector3d dq = f.Tlu.solve(rhs);
      q_[k] += dq;
      for (int comp = 0; comp < 2; ++comp) {
        const Eigen::VectorXd dl = -Sg[comp] - f.SinvK[comp] * dq;
        for (std::size_t a = 0; a < p.ring.size(); ++a)
          for (int x = 0; x < p.ring[a].count; ++x)
            rhs_[comp][std::size_t(p.ring[a].nodes[std::size_t(x)])] += p.ring[a].weights[std::size_t(x)] * dl[Eigen::Index(a)];
        for (const auto& d : p.deep) rhs_[comp][std::size_t(d.nodes[0])] += c_ * rigid_row(comp, d.offset).dot(dq);
      }
    }
    A_.solve_pair(rhs_[0].data(), rhs_[1].data(), rhs_[0].data(), rhs_[1].data());
    for (int comp = 0; comp < 2; ++comp) {
      for (std::size_t k = 0; k < n; ++k) u[comp][k] += rhs_[comp][k];
      std::fill(rhs_[comp].begin(), rhs_[comp].end(), 0.0);
    }
  }
  last_.iterations = it;
  last_.residual = residual;
}

std::vector<Eigen::Vector3d> DiskConstraint::rigid_motion(const VelocityField& u) const {
  std::vector<Eigen::Vector3d> q;
  const std::size_t nx = std::size_t(m_.nx);
  const double* field[2] = {u.u1.data() + nx, u.u2.data() + nx};  // interior rows
  for (const DiskPoints& p : points_) {
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const auto* set : {&p.ring, &p.deep})
      for (const auto& pt : *set)
        for (int comp = 0; comp < 2; ++comp) {
          const Eigen::RowVector3d row = rigid_row(comp, pt.offset);
          N += row.transpose() * row;
          rhs += row.transpose() * read(field[comp], pt);
        }
    q.push_back(N.ldlt().solve(rhs));
  }
  return q;
}

}  // namespace rbc
