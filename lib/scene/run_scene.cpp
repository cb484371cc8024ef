#include "scene/run_scene.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "diagnostics/flow_diagnostics.hpp"
#include "io/progress.hpp"
#include "io/vtk.hpp"

namespace rbc {

namespace fs = std::filesystem;

void prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw SceneError(dir + ": cannot create the output folder (" + ec.message() + ")");
  const fs::path probe = fs::path(dir) / ".rbcflow-write-test";
  {
    std::ofstream f(probe);
    if (!f) throw SceneError(dir + ": the output folder is not writable");
  }
  fs::remove(probe, ec);
}

namespace {

// Capillary numbers of the membrane in the cell-free flow (wall shear rate γ̇ = 6 U0 / H):
//   stretching  Ca_l = μ γ̇ R0 l0 / k_l    (viscous force on a spring over its elastic force)
//   bending     Ca_b = μ γ̇ R0³ / (k_b l0 / 4)
void print_membrane_header(const Scene& s, const MembraneModel& m) {
  const double U0 = s.driving_force() * s.height * s.height / (12 * s.fluid.viscosity);
  const double shear = 6 * U0 / s.height, l0 = m.rest_length(), mu = s.fluid.viscosity;
  std::fprintf(stderr,
               "rbcflow: membrane units '%s': k_l = %.3g J/m, k_b = %.3g J/m, k_s = %.3g J/m; wall shear rate %.4g 1/s; "
               "capillary numbers Ca_l = mu*gamma*R0*l0/k_l = %.3g, Ca_b = mu*gamma*R0^3/(k_b*l0/4) = %.3g\n",
               s.membrane_constants.units.c_str(), m.kl, m.kb, m.ks, shear, mu * shear * m.radius * l0 / m.kl,
               mu * shear * std::pow(m.radius, 3) / (m.kb * l0 / 4));
}

void write_membranes(std::ofstream& f, const std::vector<Cell>& cells, double t) {
  f << "# t = " << t << " s\n";
  for (std::size_t k = 0; k < cells.size(); ++k) {
    f << "# cell " << k << "\n";
    for (const auto& p : cells[k].nodes) f << p.x() << " " << p.y() << "\n";
    f << cells[k].nodes.front().x() << " " << cells[k].nodes.front().y() << "\n\n";
  }
  f << "\n";
}

}  // namespace

RunSummary run_scene(const Scene& scene, const RunOptions& opt) {
  prepare_output_dir(opt.out_dir);
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const fs::path out(opt.out_dir);
  if (scene.vtk) fs::create_directories(out / "vtk");

  Simulation sim(scene);
  const ChannelFlow& flow = sim.flow();
  const auto& cells = sim.cells();
  const double l0 = sim.membrane().rest_length();
  if (!cells.empty() && opt.progress) print_membrane_header(scene, sim.membrane());
  const long total = std::lround(std::ceil(scene.end / scene.dt - 1e-9));
  const long every = std::max(1L, std::lround(scene.sample_interval() / scene.dt));
  const double fluid_area = scene.length * scene.height;

  std::ofstream series(out / "series.csv");
  series << "t,mean_velocity,reynolds,hematocrit,max_speed,cg_iterations,coupling_iterations";
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (const char* q : {"x", "y", "area", "perimeter", "area_drift", "max_strain"}) series << ",cell" << k << "_" << q;
  series << "\n";
  series.precision(10);
  std::ofstream snapshots;
  if (!cells.empty()) snapshots.open(out / "snapshots.dat");
  std::size_t next_snapshot = 0;
  int vtk_count = 0;
  // The mean velocity of a sample is its average over the steps since the previous sample
  // (the instantaneous value at t = 0).
  double u_sum = 0;
  long u_count = 0;
  double last_mean = mean_velocity(flow.mesh(), flow.velocity());
  auto sample = [&] {
    if (u_count > 0) last_mean = u_sum / u_count;
    u_sum = 0;
    u_count = 0;
    series << sim.time() << "," << last_mean << "," << reynolds_number(last_mean, scene.fluid, scene.height) << ","
           << hematocrit_percent(cells, fluid_area) << "," << max_speed(flow.velocity()) << "," << sim.last_cg_iterations() << "," << sim.last_coupling_iterations();
    for (const Cell& c : cells) {
      const CellState s = measure_cell(c, l0);
      series << "," << s.centroid.x() << "," << s.centroid.y() << "," << s.area << "," << s.perimeter << ","
             << s.area_drift << "," << s.max_strain;
    }
    series << "\n";
    series.flush();
    if (scene.vtk) {
      char name[32];
      std::snprintf(name, sizeof name, "flow_%05d.vtk", vtk_count++);
      write_velocity_vtk((out / "vtk" / name).string(), flow.mesh(), flow.velocity(), sim.time());
    }
  };
  auto snapshot_due = [&] {
    while (next_snapshot < scene.snapshots.size() && scene.snapshots[next_snapshot] <= sim.time() + 0.5 * scene.dt) {
      write_membranes(snapshots, cells, sim.time());
      ++next_snapshot;
    }
  };

  ProgressMeter progress(opt.label, total, total * scene.dt, opt.progress);
  sample();
  if (!cells.empty()) snapshot_due();
  while (sim.steps() < total) {
    sim.step();
    sim.check_health();
    u_sum += mean_velocity(flow.mesh(), flow.velocity());
    ++u_count;
    if (sim.steps() % every == 0 || sim.steps() == total) sample();
    if (!cells.empty()) snapshot_due();
    progress.update(sim.steps(), sim.time());
  }
  progress.finish(sim.steps(), sim.time());

  RunSummary s;
  s.steps = sim.steps();
  s.t_end = sim.time();
  s.wall_seconds = progress.elapsed_seconds();
  s.mean_velocity = last_mean;
  s.reynolds = reynolds_number(s.mean_velocity, scene.fluid, scene.height);
  s.max_speed = max_speed(flow.velocity());
  s.hematocrit = hematocrit_percent(cells, fluid_area);
  for (const Cell& c : cells) s.cells.push_back(measure_cell(c, l0));

  // The x1-averaged velocity profile at the end, for plots against the Poiseuille parabola.
  {
    std::ofstream prof(out / "profile.csv");
    prof << "y,u1,u2\n";
    prof.precision(10);
    const ChannelMesh& m = flow.mesh();
    for (int jy = 0; jy <= m.ny; ++jy) {
      double a = 0, b = 0;
      for (int i = 0; i < m.nx; ++i) { a += flow.velocity().u1[m.v(i, jy)]; b += flow.velocity().u2[m.v(i, jy)]; }
      prof << m.y(jy) << "," << a / m.nx << "," << b / m.nx << "\n";
    }
  }
  if (!cells.empty()) {
    std::ofstream fin(out / "membranes_final.dat");
    write_membranes(fin, cells, sim.time());
  }

  nlohmann::ordered_json j;
  j["steps"] = s.steps;
  j["t_end"] = s.t_end;
  j["wall_seconds"] = s.wall_seconds;
  j["mean_velocity"] = s.mean_velocity;
  j["mean_velocity_averaging"] = "time average over the last sample interval (output.every)";
  j["reynolds"] = s.reynolds;
  j["hematocrit"] = s.hematocrit;
  j["cells"] = nlohmann::json::array();
  for (const CellState& c : s.cells)
    j["cells"].push_back({{"centroid", {c.centroid.x(), c.centroid.y()}},
                          {"area", c.area},
                          {"perimeter", c.perimeter},
                          {"area_drift", c.area_drift},
                          {"max_strain", c.max_strain},
                          {"shape", {{"kind", c.shape.kind},
                                     {"rear_concavity", c.shape.rear_concavity},
                                     {"front_concavity", c.shape.front_concavity},
                                     {"side_concavity", c.shape.side_concavity},
                                     {"fore_aft", c.shape.fore_aft},
                                     {"length", c.shape.length},
                                     {"width", c.shape.width}}}});
  j["disks"] = nlohmann::json::array();
  j["max_speed"] = s.max_speed;
  j["reynolds0"] = scene.reynolds0 ? nlohmann::json(*scene.reynolds0) : nlohmann::json(nullptr);
  j["body_force"] = scene.driving_force();
  j["mesh"] = {{"nx", flow.mesh().nx}, {"ny", flow.mesh().ny}, {"h", scene.mesh_size}};
  j["dt"] = scene.dt;
  j["coupling"] = scene.coupling;
  if (!cells.empty())
    j["membrane"] = {{"units", scene.membrane_constants.units}, {"kl", sim.membrane().kl}, {"kb", sim.membrane().kb},
                     {"ks", sim.membrane().ks}, {"area_penalty", scene.area_penalty}, {"nodes", scene.membrane_nodes},
                     {"radius", scene.membrane_radius}};
  j["threads"] = omp_get_max_threads();
  j["scene"] = scene.source;
  j["version"] = RBCFLOW_VERSION;
  j["units"] = "SI: m, s, kg; velocities m/s, forces N/m^3, areas m^2, hematocrit %";
  std::ofstream(out / "summary.json") << j.dump(2) << "\n";
  return s;
}

std::optional<RunSummary> read_finished_run(const std::string& dir, const Scene& scene) {
  const fs::path path = fs::path(dir) / "summary.json";
  if (!fs::exists(path)) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
    if (j.at("scene") != scene.source || j.at("dt") != scene.dt || j.at("coupling") != scene.coupling ||
        std::abs(j.at("t_end").get<double>() - scene.end) > scene.dt)  // the run ends at the first step at or past end
      return std::nullopt;
    RunSummary s;
    s.steps = j.at("steps");
    s.t_end = j.at("t_end");
    s.wall_seconds = j.at("wall_seconds");
    s.mean_velocity = j.at("mean_velocity");
    s.reynolds = j.at("reynolds");
    s.hematocrit = j.at("hematocrit");
    s.max_speed = j.at("max_speed");
    for (const auto& c : j.at("cells")) {
      CellState cs;
      cs.centroid = Eigen::Vector2d(c.at("centroid")[0].get<double>(), c.at("centroid")[1].get<double>());
      cs.area = c.at("area");
      cs.perimeter = c.at("perimeter");
      cs.area_drift = c.at("area_drift");
      cs.max_strain = c.at("max_strain");
      const auto& sh = c.at("shape");
      cs.shape.kind = sh.at("kind");
      cs.shape.rear_concavity = sh.at("rear_concavity");
      cs.shape.front_concavity = sh.at("front_concavity");
      cs.shape.side_concavity = sh.at("side_concavity");
      cs.shape.fore_aft = sh.at("fore_aft");
      cs.shape.length = sh.at("length");
      cs.shape.width = sh.at("width");
      s.cells.push_back(cs);
    }
    return s;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable or from another version: run again
  }
}

}  // namespace rbc
