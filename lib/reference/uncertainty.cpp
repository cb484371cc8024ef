#include "reference/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <stdexcept>

namespace rbc {

namespace {

std::string g(double v, int digits) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// A least-squares fit φ_k ≈ c_0 + Σ_j c_j x_j(h_k) by modified Gram–Schmidt (the columns h^a and
// h^b are far apart in scale; the normal equations would lose digits).
struct LinearFit {
  std::vector<double> c;      // c_0 (the limit), then the coefficients of the columns
  std::vector<double> value;  // the fit at each level
  double ssr = 0;             // the sum of the squared residuals
  int dof = 0;                // n − unknowns
  bool ok = false;
};

LinearFit fit_linear(const std::vector<double>& f, const std::vector<std::vector<double>>& cols) {
  const std::size_t n = f.size(), m = cols.size() + 1;
  LinearFit fit;
  fit.dof = static_cast<int>(n) - static_cast<int>(m);
  if (fit.dof < 0) return fit;
  std::vector<std::vector<double>> q(m, std::vector<double>(n));
  std::vector<std::vector<double>> r(m, std::vector<double>(m, 0.0));
  for (std::size_t j = 0; j < m; ++j) {
    std::vector<double> v = j == 0 ? std::vector<double>(n, 1.0) : cols[j - 1];
    for (std::size_t i = 0; i < j; ++i) {
      double d = 0;
      for (std::size_t k = 0; k < n; ++k) d += q[i][k] * v[k];
      r[i][j] = d;
      for (std::size_t k = 0; k < n; ++k) v[k] -= d * q[i][k];
    }
    double norm = 0;
    for (double x : v) norm += x * x;
    norm = std::sqrt(norm);
    double scale = 0;
    for (std::size_t k = 0; k < n; ++k) scale = std::max(scale, std::abs(j == 0 ? 1.0 : cols[j - 1][k]));
    if (!(norm > 1e-12 * scale)) return fit;  // dependent columns
    r[j][j] = norm;
    for (std::size_t k = 0; k < n; ++k) q[j][k] = v[k] / norm;
  }
  std::vector<double> qtf(m, 0.0);
  for (std::size_t j = 0; j < m; ++j)
    for (std::size_t k = 0; k < n; ++k) qtf[j] += q[j][k] * f[k];
  fit.c.assign(m, 0.0);
  for (std::size_t j = m; j-- > 0;) {
    double s = qtf[j];
    for (std::size_t i = j + 1; i < m; ++i) s -= r[j][i] * fit.c[i];
    fit.c[j] = s / r[j][j];
  }
  fit.value.assign(n, fit.c[0]);
  for (std::size_t j = 1; j < m; ++j)
    for (std::size_t k = 0; k < n; ++k) fit.value[k] += fit.c[j] * cols[j - 1][k];
  double scale = 0;
  for (std::size_t k = 0; k < n; ++k) {
    fit.ssr += (f[k] - fit.value[k]) * (f[k] - fit.value[k]);
    scale += f[k] * f[k];
  }
  if (fit.ssr <= 1e-26 * scale) fit.ssr = 0;  // rounding: an exact fit
  fit.ok = true;
  return fit;
}

std::vector<double> powers(const std::vector<double>& h, double p) {
  std::vector<double> x(h.size());
  for (std::size_t k = 0; k < h.size(); ++k) x[k] = std::pow(h[k], p);
  return x;
}

double sigma_of(const LinearFit& fit) { return fit.ok && fit.dof > 0 ? std::sqrt(fit.ssr / fit.dof) : NAN; }

// The sum of the squared residuals of φ_k ≈ φ_0 + α h_k^p, the residuals taken one by one (a
// closed form by sums would lose the digits that locate p in exact data).
double ssr_at_order(const std::vector<double>& f, const std::vector<double>& h, double p) {
  const std::size_t n = f.size();
  double xm = 0, fm = 0;
  for (std::size_t k = 0; k < n; ++k) {
    xm += std::pow(h[k], p);
    fm += f[k];
  }
  xm /= n;
  fm /= n;
  double sxx = 0, sxf = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double dx = std::pow(h[k], p) - xm;
    sxx += dx * dx;
    sxf += dx * (f[k] - fm);
  }
  if (!(sxx > 0)) return INFINITY;
  const double alpha = sxf / sxx, phi0 = fm - alpha * xm;
  double ssr = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double e = f[k] - phi0 - alpha * std::pow(h[k], p);
    ssr += e * e;
  }
  return ssr;
}

// δ_RE with the observed order: for each p the limit and α are linear, so the sum of squares is
// minimised over p alone (a scan over [−4q, 8q], then golden sections around the best point).
LinearFit fit_observed_order(const std::vector<double>& f, const std::vector<double>& h, double q, double& p) {
  auto ssr = [&](double pp) { return ssr_at_order(f, h, pp); };
  const double lo = -4 * q, hi = 8 * q, step = 0.02 * q;
  double best = NAN, best_ssr = INFINITY;
  for (int i = 0; lo + i * step <= hi + 0.5 * step; ++i) {
    const double pp = lo + i * step;
    if (std::abs(pp) < 0.5 * step) continue;  // h^0 is the constant column
    const double s = ssr(pp);
    if (s < best_ssr) { best_ssr = s; best = pp; }
  }
  if (!std::isfinite(best)) { p = NAN; return {}; }
  double a = best - step, b = best + step;
  const double golden = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = b - golden * (b - a), x2 = a + golden * (b - a), s1 = ssr(x1), s2 = ssr(x2);
  for (int it = 0; it < 200 && b - a > 1e-14 * std::max(1.0, std::abs(best)); ++it) {
    if (s1 <= s2) { b = x2; x2 = x1; s2 = s1; x1 = b - golden * (b - a); s1 = ssr(x1); }
    else { a = x1; x1 = x2; s1 = s2; x2 = a + golden * (b - a); s2 = ssr(x2); }
  }
  p = s1 <= s2 ? x1 : x2;
  if (best_ssr < std::min(s1, s2)) p = best;
  return fit_linear(f, {powers(h, p)});
}

}  // namespace

RefinementUncertainty grid_convergence_index(const std::vector<double>& f, double r, double formal, int reported, double noise) {
  if (f.size() < 2) throw std::invalid_argument("grid_convergence_index: needs at least two levels");
  if (!(r > 1) || !(formal > 0)) throw std::invalid_argument("grid_convergence_index: needs a ratio > 1 and a formal order > 0");
  if (reported < 0 || std::size_t(reported) >= f.size())
    throw std::invalid_argument("grid_convergence_index: the reported level is one of the levels given (0: the finest)");
  if (noise < 0) throw std::invalid_argument("grid_convergence_index: the noise is a standard deviation, >= 0 (NaN: not known)");
  const std::size_t n = f.size();
  const double q = formal;
  const bool noise_known = std::isfinite(noise);
  RefinementUncertainty u;
  u.levels = static_cast<int>(n);
  u.reported = reported;
  u.noise = noise;
  u.observed_order = NAN;
  u.order_used = q;
  u.formal_order = q;
  u.values = f;
  u.ratio = r;
  if (!std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); })) {  // no estimate (as the GCI gave)
    u.u = u.extrapolated = u.safety_factor = NAN;
    return u;
  }
  const auto [lo_it, hi_it] = std::minmax_element(f.begin(), f.end());
  u.data_range = (*hi_it - *lo_it) / (n - 1);
  std::vector<double> h(n);
  for (std::size_t k = 0; k < n; ++k) h[k] = std::pow(r, static_cast<double>(k));
  const double hr = h[reported];

  if (*hi_it == *lo_it) {  // all equal: no error to see
    u.fit = RefinementFit::Constant;
    u.safety_factor = 1.25;
    u.fit_sigma = n > 2 ? 0.0 : NAN;
    u.u = noise_known ? 2 * noise : 0.0;
    u.extrapolated = f[0];
    u.noise_dominated = noise_known && noise > 0;
    return u;
  }

  // The fixed orders: 1 and 2 (q and 2q for q < 1).
  const double pa = std::min(q, 1.0), pb = 2 * pa;
  const LinearFit low_fit = fit_linear(f, {powers(h, pa)});
  // Noise: the slope of δ_a within two of its standard errors of zero.
  if (noise_known) {
    const std::vector<double> x = powers(h, pa);
    const double mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
    double sxx = 0;
    for (double v : x) sxx += (v - mean) * (v - mean);
    const double se = noise / std::sqrt(sxx), alpha = low_fit.c[1];
    if (std::abs(alpha) <= 2 * se) {
      u.fit = RefinementFit::Noise;
      u.noise_dominated = true;
      u.safety_factor = NAN;
      u.order_used = pa;
      u.fit_sigma = std::max(sigma_of(low_fit), noise);
      u.extrapolated = low_fit.c[0];
      u.u = 2 * noise + (std::abs(alpha) + 2 * se) * std::pow(hr, pa);
      return u;
    }
  }

  if (n == 2) {  // Roache's GCI: the formal order, F_s = 3
    const double denom = std::pow(r, q) - 1, e21 = f[1] - f[0];
    u.fit = RefinementFit::TwoLevels;
    u.safety_factor = 3.0;
    u.fit_sigma = noise_known ? noise : NAN;
    u.extrapolated = f[0] - e21 / denom;
    u.u = 3.0 * std::abs(e21) * std::pow(hr, q) / denom + (noise_known ? 2 * noise : 0.0);
    return u;
  }

  bool monotone = true;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double a = f[k] - f[k - 1], b = f[k + 1] - f[k];
    if (a == 0 || b == 0 || (a > 0) != (b > 0)) monotone = false;
  }
  const double p_lo = 0.25 * q, p_hi = q, p_fs = 1.05 * q;

  struct Candidate {
    LinearFit fit;
    RefinementFit kind;
    double order, sigma;
  };
  auto eps_of = [&](const LinearFit& fit) { return std::abs(fit.value[reported] - fit.c[0]); };
  const LinearFit high_fit = fit_linear(f, {powers(h, pb)});
  // n = 3, the few-points rule: the fits with one degree of freedom measure the scatter.
  const double few_sigma = n == 3 ? std::min(sigma_of(low_fit), sigma_of(high_fit)) : NAN;
  std::vector<Candidate> fixed = {{low_fit, RefinementFit::FixedLow, pa, sigma_of(low_fit)}, {high_fit, RefinementFit::FixedHigh, pb, sigma_of(high_fit)}};
  if (n >= 4) {
    const LinearFit two = fit_linear(f, {powers(h, pa), powers(h, pb)});
    fixed.push_back({two, RefinementFit::TwoTerm, pa, sigma_of(two)});
  }
  // The paper's choice: δ_RE for a monotone sequence with p in [p_lo, p_hi], else the fixed-order
  // fit with the smallest σ.
  std::optional<Candidate> choice;
  if (monotone) {
    double p = NAN;
    LinearFit re;
    if (n == 3) {
      p = std::log((f[2] - f[1]) / (f[1] - f[0])) / std::log(r);
      if (p != 0) re = fit_linear(f, {powers(h, p)});
    } else {
      re = fit_observed_order(f, h, q, p);
    }
    if (re.ok) u.observed_order = p;
    if (re.ok && p >= p_lo && p <= p_hi) choice = Candidate{re, RefinementFit::ObservedOrder, p, n == 3 ? few_sigma : sigma_of(re)};
  }
  if (!choice)
    for (const Candidate& c : fixed)
      if (std::isfinite(c.sigma) && (!choice || c.sigma < choice->sigma)) choice = c;
  // With s given, every fit within max(σ, 2 s) of the data is consistent with it: the data
  // cannot tell them apart, so the one with the largest error estimate is taken.
  if (noise_known) {
    const double consistent = std::max(choice->sigma, 2 * noise);
    for (const Candidate& c : fixed)
      if (c.sigma <= consistent && eps_of(c.fit) > eps_of(choice->fit)) choice = c;
  }
  const LinearFit& used = choice->fit;
  u.fit = choice->kind;
  u.order_used = choice->order;
  const double sigma = choice->sigma;
  const double sigma_star = noise_known ? std::max(sigma, noise) : sigma;
  u.fit_sigma = sigma_star;
  u.extrapolated = used.c[0];
  const double eps = std::abs(used.value[reported] - used.c[0]), res = std::abs(f[reported] - used.value[reported]);
  const double p = u.observed_order;
  const bool order_ok = monotone && std::isfinite(p) && p >= p_lo && p < p_fs;
  if (sigma_star < u.data_range) {
    u.safety_factor = order_ok ? 1.25 : 3.0;
    u.u = u.safety_factor * eps + sigma_star + res;
  } else {
    u.safety_factor = 3.0;
    u.noise_dominated = true;  // the scatter is larger than the steps: no order is observed
    u.observed_order = NAN;
    u.u = 3.0 * sigma_star / u.data_range * (eps + sigma_star + res);
  }
  return u;
}

std::string RefinementUncertainty::describe(int digits) const {
  std::string s = label.empty() ? "" : label + ": ";
  const std::string of = reported == 0 ? "" : reported == 1 ? " of the second finest" : " of level " + std::to_string(reported) + " (0 the finest)";
  const std::string fixed = fit == RefinementFit::TwoTerm ? g(order_used, 2) + " and " + g(2 * order_used, 2) : g(order_used, 2);
  switch (fit) {
    case RefinementFit::Noise:
      return s + "noise: no convergence observed (s " + g(noise, digits) + "), U " + g(u, digits) + of;
    case RefinementFit::Constant:
      return s + "all levels equal, U " + g(u, digits) + of;
    case RefinementFit::TwoLevels:
      s += "two levels, p = " + g(order_used, 2) + " assumed";
      if (std::isfinite(fit_sigma)) s += ", s " + g(fit_sigma, digits);
      break;
    default:
      if (noise_dominated)
        s += "noise: no convergence observed (fit σ " + g(fit_sigma, digits) + " >= Δφ " + g(data_range, digits) + "); fit p = " + fixed;
      else if (fit == RefinementFit::ObservedOrder)
        s += "p = " + g(observed_order, 2) + ", fit σ " + g(fit_sigma, digits);
      else
        s += (std::isfinite(observed_order) ? "p = " + g(observed_order, 2) : std::string("no order observed")) + "; fit p = " + fixed + ", fit σ " +
             g(fit_sigma, digits);
  }
  s += ", U " + g(u, digits) + of + " (Fs " + g(safety_factor, 3) + ")";
  if (const auto R = richardson(*this))  // the change, not the value: records keep values relative to a level
    s += " [Richardson: the limit " + std::string(R->value >= values[0] ? "+" : "") + g(R->value - values[0], digits) + " from the finest" +
         (std::isfinite(R->u) ? " ± " + g(R->u, digits) + "]" : ", two levels: no U of its own]");
  return s;
}

std::optional<RichardsonEstimate> richardson(const RefinementUncertainty& r) {
  const std::vector<double>& f = r.values;
  if (f.size() < 2 || !(r.ratio > 1) || !(r.formal_order > 0) || r.noise_dominated) return std::nullopt;
  if (std::isfinite(r.noise) && r.noise > 0) return std::nullopt;  // a spread of starts given: a chaotic quantity
  if (!std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); })) return std::nullopt;
  if (r.fit == RefinementFit::Noise || r.fit == RefinementFit::Constant) return std::nullopt;
  if (f.size() >= 3 && r.safety_factor != 1.25) return std::nullopt;  // outside the asymptotic range
  RichardsonEstimate e;
  e.value = richardson_extrapolate(f[0], f[1], r.ratio, r.formal_order);
  // (and at least its distance to the estimator's own limit: an observed order below q leaves
  // more than the formal extrapolation removes)
  if (f.size() >= 3)
    e.u = std::max(1.25 * std::abs(e.value - richardson_extrapolate(f[1], f[2], r.ratio, r.formal_order)), std::abs(e.value - r.extrapolated));
  return e;
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
  auto twice = [](std::optional<double> x) { return x ? std::optional<double>(2 * *x) : x; };
  if (dt) add(dt->u);
  const double per = of_mean && members > 0 ? 1 / std::sqrt(double(members)) : 1.0;  // a mean's: s/√n
  add(ensemble ? std::optional<double>(2 * per * *ensemble) : ensemble);  // 1σ parts at 95 %: k = 2
  add(twice(window));
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
  if (ensemble && std::isfinite(*ensemble))
    part(std::string("ensemble of ").append(std::to_string(members)).append(": s ").append(g(*ensemble, digits)).append(of_mean ? " (their mean: 2 s/√n at 95 %)" : " (2 s at 95 %)"));
  if (window && std::isfinite(*window)) part(std::string("window noise ").append(g(*window, digits)).append(" (x2)"));
  if (!missing.empty()) part("missing: " + missing);
  if (!other.empty()) {
    std::string o = other;
    if (other_value && std::isfinite(*other_value)) o.append(" ").append(g(*other_value, digits));
    part(o);
  }
  if (!provenance.empty()) part(provenance);
  return s;
}

}  // namespace rbc
