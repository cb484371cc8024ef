#include "scene/run_scene.hpp"

#include <cmath>
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

RunSummary run_scene(const Scene& scene, const RunOptions& opt) {
  prepare_output_dir(opt.out_dir);
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const fs::path out(opt.out_dir);
  if (scene.vtk) fs::create_directories(out / "vtk");

  Simulation sim(scene);
  const ChannelFlow& flow = sim.flow();
  const long total = std::lround(std::ceil(scene.end / scene.dt - 1e-9));
  const long every = std::max(1L, std::lround(scene.sample_interval() / scene.dt));

  std::ofstream series(out / "series.csv");
  series << "t,mean_velocity,reynolds,hematocrit,max_speed,cg_iterations\n";
  series.precision(10);
  int vtk_count = 0;
  auto sample = [&] {
    const double U = mean_velocity(flow.mesh(), flow.velocity());
    series << sim.time() << "," << U << "," << reynolds_number(U, scene.fluid, scene.height) << ",0,"
           << max_speed(flow.velocity()) << "," << sim.last_cg_iterations() << "\n";
    series.flush();
    if (scene.vtk) {
      char name[32];
      std::snprintf(name, sizeof name, "flow_%05d.vtk", vtk_count++);
      write_velocity_vtk((out / "vtk" / name).string(), flow.mesh(), flow.velocity(), sim.time());
    }
  };

  ProgressMeter progress("rbcflow", total, total * scene.dt, opt.progress);
  sample();
  while (sim.steps() < total) {
    sim.step();
    sim.check_health();
    if (sim.steps() % every == 0 || sim.steps() == total) sample();
    progress.update(sim.steps(), sim.time());
  }
  progress.finish(sim.steps(), sim.time());

  RunSummary s;
  s.steps = sim.steps();
  s.t_end = sim.time();
  s.wall_seconds = progress.elapsed_seconds();
  s.mean_velocity = mean_velocity(flow.mesh(), flow.velocity());
  s.reynolds = reynolds_number(s.mean_velocity, scene.fluid, scene.height);
  s.max_speed = max_speed(flow.velocity());

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

  nlohmann::ordered_json j;
  j["steps"] = s.steps;
  j["t_end"] = s.t_end;
  j["wall_seconds"] = s.wall_seconds;
  j["mean_velocity"] = s.mean_velocity;
  j["reynolds"] = s.reynolds;
  j["hematocrit"] = 0.0;
  j["cells"] = nlohmann::json::array();
  j["disks"] = nlohmann::json::array();
  j["max_speed"] = s.max_speed;
  j["reynolds0"] = scene.reynolds0 ? nlohmann::json(*scene.reynolds0) : nlohmann::json(nullptr);
  j["body_force"] = scene.driving_force();
  j["mesh"] = {{"nx", flow.mesh().nx}, {"ny", flow.mesh().ny}, {"h", scene.mesh_size}};
  j["dt"] = scene.dt;
  j["threads"] = omp_get_max_threads();
  j["scene"] = scene.source;
  j["version"] = RBCFLOW_VERSION;
  j["units"] = "SI: m, s, kg; velocities m/s, forces N/m^3";
  std::ofstream(out / "summary.json") << j.dump(2) << "\n";
  return s;
}

}  // namespace rbc
