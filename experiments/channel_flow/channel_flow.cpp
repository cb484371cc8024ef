#include "channel_flow.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

namespace rbc::channel_flow {

namespace {

// Mean velocity of the start-up from rest (the Fourier series averaged over the height):
//   U(t) = U0 (1 − Σ_{n odd} 96/(π⁴ n⁴) exp(−n² π² ν t / H²)).
double startup_mean(double u0, double nu, double H, double t) {
  const double pi = std::numbers::pi;
  double s = 0;
  for (int n = 1; n < 200; n += 2) s += 96.0 / (std::pow(pi, 4) * std::pow(n, 4)) * std::exp(-n * n * pi * pi * nu * t / (H * H));
  return u0 * (1.0 - s);
}

std::vector<std::vector<double>> read_csv_numbers(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) r.push_back(std::stod(cell));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

Results run(const Params& p) {
  Results res;
  for (const std::string which : {"narrow", "wide"}) {
    // The scene file beside this source holds the channel's parameters, once.
    const std::string scene_path = std::string(RBCFLOW_SOURCE_DIR) + "/experiments/channel_flow/" + which + ".toml";
    std::vector<std::string> overrides;
    if (p.quick) overrides.push_back(which == "narrow" ? "time.dt=5e-7" : "time.dt=1.5e-6");
    const Scene scene = load_scene_file(scene_path, overrides);
    const std::string out = (std::filesystem::path(p.out_dir) / which).string();
    ChannelResult r;
    r.summary = run_scene(scene, {out, p.threads, p.progress});

    // Compare with the exact solutions: the parabola at the end, the mean during start-up.
    const double mu = scene.fluid.viscosity, nu = mu / scene.fluid.density, H = scene.height;
    const double f = scene.driving_force(), u0 = f * H * H / (12 * mu), peak = 1.5 * u0;
    std::ofstream profile(std::filesystem::path(out) / "profile_vs_parabola.csv");
    profile << "y,u1,parabola\n";
    for (const auto& row : read_csv_numbers(std::filesystem::path(out) / "profile.csv")) {
      const double exact = f * row[0] * (H - row[0]) / (2 * mu);
      profile << row[0] << "," << row[1] << "," << exact << "\n";
      r.profile_error = std::max(r.profile_error, std::abs(row[1] - exact) / peak);
    }
    std::ofstream startup(std::filesystem::path(out) / "startup.csv");
    startup << "t,mean_velocity,exact_p1_mean\n";
    const double p1 = 1.0 - std::pow(scene.mesh_size / H, 2);  // the P1 mean of the nodal parabola
    for (const auto& row : read_csv_numbers(std::filesystem::path(out) / "series.csv")) {
      const double exact = startup_mean(u0, nu, H, row[0]) * p1;
      startup << row[0] << "," << row[1] << "," << exact << "\n";
      r.startup_error = std::max(r.startup_error, std::abs(row[1] - exact) / u0);
    }
    res.measured[which + "_mean_velocity"] = {r.summary.mean_velocity * 100.0, {}, ""};  // cm/s
    res.measured[which + "_reynolds"] = {r.summary.reynolds, {}, ""};
    res.channels[which] = r;
  }
  return res;
}

}  // namespace rbc::channel_flow
