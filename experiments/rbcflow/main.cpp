// rbcflow — the generic scene runner (SPEC section 8).
//   build/bin/rbcflow run SCENE.toml --out DIR [--threads N] [--set key=value ...]
#include <cstdio>

#include <CLI/CLI.hpp>

#include "scene/run_scene.hpp"

int main(int argc, char** argv) {
  CLI::App app{"rbcflow: red blood cells in Poiseuille flows (Shi, Pan & Glowinski 2012, DOI 10.1002/fld.2455)"};
  app.require_subcommand(1);
  std::string scene_path, out_dir;
  int threads = 0;
  bool quiet = false;
  std::vector<std::string> overrides;
  CLI::App* run = app.add_subcommand("run", "run a scene described in a TOML file (SI units)");
  run->add_option("scene", scene_path, "scene file (.toml)")->required();
  run->add_option("--out", out_dir, "output folder (default: results/<scene name>/)");
  run->add_option("--threads", threads, "OpenMP threads (default: all cores)")->check(CLI::Range(1, 256));
  run->add_option("--set", overrides, "override a scene key: table.key=value (TOML value)");
  run->add_flag("--quiet", quiet, "no progress line");
  CLI11_PARSE(app, argc, argv);

  try {
    const rbc::Scene scene = rbc::load_scene_file(scene_path, overrides);
    if (out_dir.empty()) out_dir = "results/" + std::filesystem::path(scene_path).stem().string();
    const rbc::RunSummary s = rbc::run_scene(scene, {out_dir, threads, !quiet});
    std::printf("%ld steps to t = %.6g s in %.2f s; mean velocity %.6g m/s, Re = %.6g; outputs in %s\n", s.steps,
                s.t_end, s.wall_seconds, s.mean_velocity, s.reynolds, out_dir.c_str());
    return 0;
  } catch (const rbc::SceneError& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 2;
  } catch (const rbc::RunFailure& e) {
    std::fprintf(stderr, "rbcflow: run stopped: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 1;
  }
}
