#include "channel_flow.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "common/case_runner.hpp"
#include "io/csv.hpp"

namespace rbc::channel_flow {

namespace {

// Mean velocity of the start-up from rest (the Fourier series averaged over the height), and its
// time average over (t0, t1] — what series.csv records (the average over each sample interval):
//   U(t) = U0 (1 − Σ_{n odd} 96/(π⁴ n⁴) exp(−λ_n t)),   λ_n = n² π² ν / H².
double startup_mean(double u0, double nu, double H, double t0, double t1) {
  const double pi = std::numbers::pi;
  double s = 0;
  for (int n = 1; n < 200; n += 2) {
    const double lam = n * n * pi * pi * nu / (H * H);
    const double decay = (t1 > t0) ? (std::exp(-lam * t0) - std::exp(-lam * t1)) / (lam * (t1 - t0)) : std::exp(-lam * t1);
    s += 96.0 / (std::pow(pi, 4) * std::pow(n, 4)) * decay;
  }
  return u0 * (1.0 - s);
}

}  // namespace

std::vector<std::string> cases() { return {"narrow", "wide"}; }

Results run(const Params& p) {
  Results res;
  const std::vector<std::string> all = cases();
  case_runner::require_case(all, p.only, "channel_flow");
  for (const std::string& which : all) {
    if (!p.only.empty() && which != p.only) continue;
    // The scene file beside this source holds the channel's parameters, once.
    const std::string scene_path = std::string(RBCFLOW_SOURCE_DIR) + "/experiments/channel_flow/" + which + ".toml";
    std::vector<std::string> overrides;
    if (p.quick) overrides.push_back(which == "narrow" ? "time.dt=5e-7" : "time.dt=1.5e-6");
    const Scene scene = load_scene_file(scene_path, overrides);
    const std::string out = (std::filesystem::path(p.out_dir) / which).string();
    ChannelResult r;
    const case_runner::CaseRun run = case_runner::run_or_reuse(
        scene, out, {.threads = p.threads, .progress = p.progress, .resume = p.resume, .reuse = p.reuse, .label = which});
    if (!run.failure.empty()) throw RunFailure(which + " channel: " + run.failure);
    r.summary = run.summary;

    // Compare with the exact solutions: the parabola at the end, the mean during start-up.
    const double mu = scene.fluid.viscosity, nu = mu / scene.fluid.density, H = scene.height;
    const double f = scene.driving_force(), u0 = f * H * H / (12 * mu), peak = 1.5 * u0;
    const std::filesystem::path dir(out);
    std::ofstream profile(dir / "profile_vs_parabola.csv");
    profile << "y,u1,parabola\n";
    const auto y = csv_column((dir / "profile.csv").string(), "y"), u1 = csv_column((dir / "profile.csv").string(), "u1");
    for (std::size_t k = 0; k < y.size(); ++k) {
      const double exact = f * y[k] * (H - y[k]) / (2 * mu);
      profile << y[k] << "," << u1[k] << "," << exact << "\n";
      r.profile_error = std::max(r.profile_error, std::abs(u1[k] - exact) / peak);
    }
    std::ofstream startup(dir / "startup.csv");
    startup << "t,mean_velocity,exact_p1_mean\n";  // both averaged over the sample interval ending at t
    const double p1 = 1.0 - std::pow(scene.mesh_size / H, 2);  // the P1 mean of the nodal parabola
    const auto t = csv_column((dir / "series.csv").string(), "t"), U = csv_column((dir / "series.csv").string(), "mean_velocity");
    for (std::size_t k = 0; k < t.size(); ++k) {
      const double exact = startup_mean(u0, nu, H, k > 0 ? t[k - 1] : t[k], t[k]) * p1;
      startup << t[k] << "," << U[k] << "," << exact << "\n";
      r.startup_error = std::max(r.startup_error, std::abs(U[k] - exact) / u0);
    }
    if (p.quick) {
      res.quick_record[which + "_mean_velocity"] = {which + " channel: mean velocity at the end", "cm/s", r.summary.mean_velocity * 100.0};
      res.quick_record[which + "_profile_error"] = {which + " channel: max |u1 - parabola| / peak at the end", "", r.profile_error};
      res.quick_record[which + "_startup_error"] = {which + " channel: start-up, max |U - U_exact| / U0", "", r.startup_error};
      res.quick_record[which + "_steps"] = {which + " channel: steps", "", double(r.summary.steps)};
    }
    // u_num: the time stepping against the exact start-up of the P1 mean at the last sample, and
    // the start-up not yet finished (the exact mean's distance to its steady value); the mesh
    // apart: h -> 0 gives U0 itself (the P1 mean is U0 (1 - h²/H²)).
    const double exact_end = startup_mean(u0, nu, H, t.size() > 1 ? t[t.size() - 2] : t.back(), t.back()) * p1;
    // The same two parts in each row's unit: scale 100 gives cm/s, rho H / mu gives Re.
    auto parts = [&](double scale) {
      NumericalUncertainty u;
      u.other = "time stepping against the exact start-up";
      u.other_value = std::abs(U.back() - exact_end) * scale;
      u.window = std::abs(u0 * p1 - exact_end) * scale;
      return u;
    };
    const double per = r.summary.reynolds / r.summary.mean_velocity;  // Re per m/s
    char how[160], conv[160];
    std::snprintf(how, sizeof how, "cell-free; h = %g um, dt = %g s to %g ms", scene.mesh_size * 1e6, scene.dt, t.back() * 1e3);
    std::snprintf(conv, sizeof conv, "%.6g (h -> 0: U0; the P1 mean is U0 (1 - h^2/H^2), %+.2g %%)", u0 * 100, -100 * std::pow(scene.mesh_size / H, 2));
    res.measured[which + "_mean_velocity"] = {r.summary.mean_velocity * 100.0, {}, "", parts(100.0), conv, how};  // cm/s
    std::snprintf(conv, sizeof conv, "%.6g (h -> 0)", u0 * per);
    res.measured[which + "_reynolds"] = {r.summary.reynolds, {}, "", parts(per), conv, how};
    // Both rows under each reading of U (reference-data/readings.csv), at the last sample.
    const std::string series = (dir / "series.csv").string();
    res.measured[which + "_mean_velocity"].readings = case_runner::u_readings(series, t.back(), 100.0);
    res.measured[which + "_reynolds"].readings = case_runner::u_readings(series, t.back(), per);
    res.channels[which] = r;
  }
  return res;
}

}  // namespace rbc::channel_flow
