// rbcflow — the generic scene runner (README.md, paper/scene_keys.md).
//   build/bin/rbcflow run SCENE.toml --out DIR [--threads N] [--set key=value ...]
//   build/bin/rbcflow resume DIR [--threads N] [--any-code]  (continue from DIR's newest usable checkpoint to the end)
//   build/bin/rbcflow summary [--results DIR] [EXPERIMENT ...]
//                     the table of all the study's numbers (Markdown), from DIR/<experiment>/check.csv
// Exit codes: 0 done; 1 internal error; 2 bad input (scene, scene file, checkpoint, output folder);
// 105/106/109 a command line CLI11 refuses (bad value, no command, unknown option); 3 the run
// went unstable (last good checkpoint kept); 128 + signal when stopped by SIGINT/SIGTERM
// (checkpoint written).
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "io/checkpoint.hpp"
#include "reference/reference_table.hpp"
#include "scene/run_scene.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  CLI::App app{"rbcflow: red blood cells in Poiseuille flows (Shi, Pan & Glowinski 2012, DOI 10.1002/fld.2455)"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("rbcflow"), "print the code id and commit this program was built from");
  // Command-line errors in one line, like the other errors (set before the subcommands copy it).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "rbcflow: error: " + std::string(e.what()) + " (see rbcflow --help)\n";
  });
  app.require_subcommand(1);
  std::string scene_path, out_dir, resume_dir;
  int threads = 0;
  bool quiet = false;
  double checkpoint_wall = 600, checkpoint_sim = 0;
  std::vector<std::string> overrides;
  CLI::App* run = app.add_subcommand("run", "run a scene described in a TOML file (SI units)");
  run->add_option("scene", scene_path, "scene file (.toml)")->required();
  run->add_option("--out", out_dir, "output folder (default: results/<scene name>/)");
  run->add_option("--set", overrides, "override a scene key: table.key=value (TOML value)");
  bool overwrite = false;
  run->add_flag("--overwrite", overwrite, "clear another run's files from the output folder first (without it such a folder is refused)");
  CLI::App* resume = app.add_subcommand("resume", "continue a stopped run from the newest valid checkpoint in its folder");
  resume->add_option("dir", resume_dir, "output folder of the stopped run")->required();
  bool any_code = false;
  resume->add_flag("--any-code", any_code, "continue a checkpoint written by other code (refused without it; named on stderr)");
  for (CLI::App* sub : {run, resume}) {
    sub->add_option("--threads", threads, std::string(rbc::kThreadsHelp) + "; resume with the same number for identical results")
        ->check(CLI::Range(0, 256));
    sub->add_option("--checkpoint-wall", checkpoint_wall, "seconds of wall-clock time between checkpoints (0: none)")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str();
    sub->add_option("--checkpoint-sim", checkpoint_sim, "seconds of simulated time between checkpoints (0: none)")
        ->check(CLI::Range(0.0, 1e9))->capture_default_str();
    sub->add_flag("--quiet", quiet, "no progress line");
  }
  std::string results_dir = "results";
  std::vector<std::string> experiments = {"single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction"};
  CLI::App* summary = app.add_subcommand("summary", "print the table of all the study's numbers (Markdown) from the experiments' check.csv");
  summary->add_option("--results", results_dir, "folder holding <experiment>/check.csv (default results)");
  summary->add_option("experiments", experiments, "experiments, in order (default: the study's four)");
  if (argc > 1 && argv[1][0] != '-' && std::string(argv[1]) != "run" && std::string(argv[1]) != "resume" &&
      std::string(argv[1]) != "summary") {
    std::fprintf(stderr, "rbcflow: error: unknown command '%s' (commands: run, resume, summary; see rbcflow --help)\n", argv[1]);
    return 106;  // CLI11's code for a missing subcommand
  }
  CLI11_PARSE(app, argc, argv);

  try {
    if (summary->parsed()) {
      rbc::write_study_summary(experiments, results_dir, std::cout);
      return 0;
    }
    rbc::Scene scene;
    if (resume->parsed()) {
      out_dir = resume_dir;
      scene = rbc::checkpoint_scene(resume_dir, any_code);
    } else {
      scene = rbc::load_scene_file(scene_path, overrides);
      if (out_dir.empty()) out_dir = "results/" + std::filesystem::path(scene_path).stem().string();
    }
    const rbc::RunSummary s = rbc::run_scene(scene, {.out_dir = out_dir, .threads = threads, .progress = !quiet,
                                                     .checkpoint_wall = checkpoint_wall, .checkpoint_sim = checkpoint_sim,
                                                     .resume = resume->parsed(), .any_code = any_code, .refuse_other_run = !overwrite});
    std::printf("%ld steps to t = %.6g s in %.2f s; mean velocity %.6g m/s, Re = %.6g; outputs in %s\n", s.steps,
                s.t_end, s.wall_seconds, s.mean_velocity, s.reynolds, out_dir.c_str());
    return 0;
  } catch (const rbc::SceneError& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 2;
  } catch (const rbc::CheckpointError& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 2;
  } catch (const rbc::OutputError& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 2;
  } catch (const rbc::RunFailure& e) {
    std::fprintf(stderr, "rbcflow: run stopped: %s\n", e.what());
    return 3;
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "rbcflow: %s\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rbcflow: error: %s\n", e.what());
    return 1;
  }
}
