#include "membrane/shape_preparation.hpp"

#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <gsl/gsl_multimin.h>

namespace rbc {

namespace {

struct Problem {
  MembraneModel unit;  // R0 = 1, k_l = 1
  double target;       // s_e / R0²
};

Points to_points(const gsl_vector* x) {
  Points r(x->size / 2);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = {gsl_vector_get(x, 2 * i), gsl_vector_get(x, 2 * i + 1)};
  return r;
}

double energy_f(const gsl_vector* x, void* p) {
  const auto* pb = static_cast<const Problem*>(p);
  return membrane_energy(pb->unit, to_points(x), pb->target, nullptr).total();
}

void energy_df(const gsl_vector* x, void* p, gsl_vector* g) {
  const auto* pb = static_cast<const Problem*>(p);
  Points f;
  membrane_energy(pb->unit, to_points(x), pb->target, &f);
  for (std::size_t i = 0; i < f.size(); ++i) {
    gsl_vector_set(g, 2 * i, -f[i].x());
    gsl_vector_set(g, 2 * i + 1, -f[i].y());
  }
}

void energy_fdf(const gsl_vector* x, void* p, double* e, gsl_vector* g) {
  *e = energy_f(x, p);
  energy_df(x, p, g);
}

Eigen::VectorXd gradient(const Problem& pb, const Eigen::VectorXd& x) {
  Points r(x.size() / 2), f;
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = {x[2 * i], x[2 * i + 1]};
  membrane_energy(pb.unit, r, pb.target, &f);
  Eigen::VectorXd g(x.size());
  for (std::size_t i = 0; i < f.size(); ++i) { g[2 * i] = -f[i].x(); g[2 * i + 1] = -f[i].y(); }
  return g;
}

PreparedShape minimise(const MembraneModel& model, double s_star);

// What prepare_shape has minimised in this process.
struct Prepared {
  MembraneModel model;
  double s_star;
  PreparedShape shape;
};
std::mutex prepared_lock;
std::vector<Prepared> prepared;

}  // namespace

PreparedShape prepare_shape(const MembraneModel& model, double s_star) {
  if (!(s_star > 0.0 && s_star <= 1.0)) throw std::invalid_argument("swelling ratio must be in (0, 1]");
  {
    std::lock_guard<std::mutex> guard(prepared_lock);
    for (const Prepared& p : prepared)
      if (p.model == model && p.s_star == s_star) return p.shape;
  }
  PreparedShape shape = minimise(model, s_star);
  std::lock_guard<std::mutex> guard(prepared_lock);
  prepared.push_back({model, s_star, shape});
  return shape;
}

int shapes_minimised() {
  std::lock_guard<std::mutex> guard(prepared_lock);
  return int(prepared.size());
}

namespace {

PreparedShape minimise(const MembraneModel& model, double s_star) {
  const int n = model.nodes;
  const double R0 = model.radius, pi = std::numbers::pi;
  PreparedShape out;
  const bool regular = s_star >= max_swelling_ratio(n);  // the regular N-gon at rest (see the header)
  out.target_area = (regular ? max_swelling_ratio(n) : s_star) * pi * R0 * R0;
  // The regular N-gon of side l0 = 2πR0/N: circumradius l0 / (2 sin(π/N)).
  const double circumradius = model.rest_length() / (2 * std::sin(pi / n));
  Points circle(n);
  for (int i = 0; i < n; ++i) circle[i] = circumradius * Eigen::Vector2d(std::cos(2 * pi * i / n), std::sin(2 * pi * i / n));
  if (!regular) {
    Problem pb{model, s_star * pi};
    pb.unit.radius = 1.0;
    pb.unit.kl = 1.0;
    pb.unit.kb = model.kb / model.kl;
    pb.unit.ks = model.ks / model.kl;
    pb.unit.area_penalty = true;
    gsl_vector* x = gsl_vector_alloc(2 * n);
    for (int i = 0; i < n; ++i) {
      gsl_vector_set(x, 2 * i, 1.01 * std::cos(2 * pi * i / n));
      gsl_vector_set(x, 2 * i + 1, 0.99 * std::sin(2 * pi * i / n));
    }
    gsl_multimin_function_fdf fdf{&energy_f, &energy_df, &energy_fdf, std::size_t(2 * n), &pb};
    gsl_multimin_fdfminimizer* s = gsl_multimin_fdfminimizer_alloc(gsl_multimin_fdfminimizer_vector_bfgs2, 2 * n);
    gsl_multimin_fdfminimizer_set(s, &fdf, x, 1e-3, 0.1);
    int status = GSL_CONTINUE;
    for (int it = 0; it < 200000 && status == GSL_CONTINUE; ++it) {
      if (gsl_multimin_fdfminimizer_iterate(s) != GSL_SUCCESS) break;  // no progress: Newton takes over
      status = gsl_multimin_test_gradient(s->gradient, 1e-10);
      out.iterations = it + 1;
    }
    Eigen::VectorXd xv(2 * n);
    for (int k = 0; k < 2 * n; ++k) xv[k] = gsl_vector_get(s->x, k);
    gsl_multimin_fdfminimizer_free(s);
    gsl_vector_free(x);
    // Newton polish: H δ = −g with a central-difference Hessian of the exact gradient. The
    // Hessian is singular along rigid motions (3 directions); the pseudo-inverse ignores them.
    for (int it = 0; it < 8; ++it) {
      const Eigen::VectorXd g = gradient(pb, xv);
      if (g.norm() < 1e-14) break;
      Eigen::MatrixXd H(2 * n, 2 * n);
      const double eps = 1e-6;
      for (int k = 0; k < 2 * n; ++k) {
        Eigen::VectorXd xp = xv, xm = xv;
        xp[k] += eps;
        xm[k] -= eps;
        H.col(k) = (gradient(pb, xp) - gradient(pb, xm)) / (2 * eps);
      }
      H = 0.5 * (H + H.transpose());
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(H);
      const Eigen::VectorXd lam = es.eigenvalues();
      const double cut = 1e-9 * lam.cwiseAbs().maxCoeff();
      Eigen::VectorXd gt = es.eigenvectors().transpose() * g;
      for (int k = 0; k < 2 * n; ++k) gt[k] = (lam[k] > cut) ? gt[k] / lam[k] : 0.0;
      xv -= es.eigenvectors() * gt;
      ++out.iterations;
    }
    for (int i = 0; i < n; ++i) circle[i] = R0 * Eigen::Vector2d(xv[2 * i], xv[2 * i + 1]);
  }
  // Centroid at the origin, long axis along x1 (principal axis of the node cloud).
  const Eigen::Vector2d c = area_centroid(circle);
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (auto& p : circle) { p -= c; cov += p * p.transpose(); }
  if (!regular) {
    const double angle = 0.5 * std::atan2(2 * cov(0, 1), cov(0, 0) - cov(1, 1));
    const Eigen::Rotation2Dd rot(-angle);
    for (auto& p : circle) p = rot * p;
  }
  out.nodes = circle;
  out.area_error = (enclosed_area(circle) - out.target_area) / out.target_area;
  out.perimeter_error = (perimeter(circle) - 2 * pi * R0) / (2 * pi * R0);
  return out;
}

}  // namespace

double max_swelling_ratio(int nodes) {
  const double a = std::numbers::pi / nodes;
  return a / std::tan(a);
}

Points place_shape(const PreparedShape& shape, const Eigen::Vector2d& centroid, double angle) {
  const Eigen::Rotation2Dd rot(angle);
  Points r = shape.nodes;
  for (auto& p : r) p = centroid + rot * p;
  return r;
}

}  // namespace rbc
