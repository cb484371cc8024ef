#include "reference/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace rbc {

namespace {

std::string g(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace

RefinementUncertainty grid_convergence_index(const std::vector<double>& f, double r, double formal, int reported) {
  if (f.size() < 2) throw std::invalid_argument("grid_convergence_index: needs at least two levels");
  if (!(r > 1) || !(formal > 0)) throw std::invalid_argument("grid_convergence_index: needs a ratio > 1 and a formal order > 0");
  if (reported != 0 && reported != 1) throw std::invalid_argument("grid_convergence_index: the reported level is 0 (finest) or 1");
  RefinementUncertainty u;
  u.reported = reported;
  u.levels = f.size() >= 3 ? 3 : 2;
  u.observed_order = NAN;
  u.order_used = formal;
  u.safety_factor = 3.0;
  const double e21 = f[1] - f[0];
  if (u.levels == 3) {
    const double e32 = f[2] - f[1];
    if (e21 != 0 && e32 != 0 && (e21 > 0) == (e32 > 0)) {  // monotone: an order is observed
      u.observed_order = std::log(e32 / e21) / std::log(r);
      u.order_used = std::clamp(u.observed_order, 0.5 * formal, formal);
      if (u.observed_order >= 0.5 * formal && u.observed_order <= 2 * formal) u.safety_factor = 1.25;
    } else if (e21 == 0 && e32 == 0) {
      u.safety_factor = 1.25;
    }
  }
  const double denom = std::pow(r, u.order_used) - 1;
  u.u = u.safety_factor * std::abs(e21) * (reported == 1 ? std::pow(r, u.order_used) : 1.0) / denom;
  u.extrapolated = f[0] - e21 / denom;
  return u;
}

std::string RefinementUncertainty::describe(int digits) const {
  std::string s = label.empty() ? "" : label + ": ";
  if (std::isfinite(observed_order))
    s += "p = " + g(observed_order, 2);
  else
    s += levels == 3 ? "oscillating, p = " + g(order_used, 2) + " assumed" : "two levels, p = " + g(order_used, 2) + " assumed";
  s += ", GCI " + g(u, digits) + (reported == 1 ? " of the second finest" : "") + " (Fs " + g(safety_factor, 3) + ")";
  return s;
}

double sample_std(const std::vector<double>& v) {
  if (v.size() < 2) return NAN;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / (v.size() - 1));
}

double window_noise(const std::vector<double>& t, const std::vector<double>& v, double window, int count) {
  if (t.empty() || t.size() != v.size() || count < 2) return NAN;
  const double end = t.back(), eps = 1e-9 * window;
  const double spacing = t.size() > 1 ? t[1] - t[0] : 0;  // the first sample stands for the interval before it
  if (end - t.front() + spacing < count * window - eps) return NAN;
  std::vector<double> means;
  for (int w = 0; w < count; ++w) {
    const double hi = end - w * window, lo = hi - window;
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] > lo + eps && t[k] <= hi + eps) { sum += v[k]; ++n; }
    if (n == 0) return NAN;
    means.push_back(sum / n);
  }
  return sample_std(means);
}

std::optional<double> NumericalUncertainty::total() const {
  double ss = 0;
  bool any = false;
  auto add = [&](std::optional<double> x) {
    if (x && std::isfinite(*x)) { ss += *x * *x; any = true; }
  };
  if (dt) add(dt->u);
  add(ensemble);
  add(window);
  add(other_value);
  if (!any) return std::nullopt;
  return std::sqrt(ss);
}

std::string NumericalUncertainty::describe(int digits) const {
  std::string s;
  auto part = [&](const std::string& p) {
    if (!s.empty()) s += "; ";
    s += p;
  };
  if (dt) part(dt->describe(digits));
  if (ensemble && std::isfinite(*ensemble)) part(std::string("ensemble of ").append(std::to_string(members)).append(": s ").append(g(*ensemble, digits)));
  if (window && std::isfinite(*window)) part(std::string("window noise ").append(g(*window, digits)));
  if (!missing.empty()) part("missing: " + missing);
  if (!other.empty()) {
    std::string o = other;
    if (other_value && std::isfinite(*other_value)) o.append(" ").append(g(*other_value, digits));
    part(o);
  }
  return s;
}

}  // namespace rbc
