// stability_map: the largest stable Δt of both couplings against k_l, k_b and h, and extreme cases
// (see stability_map.hpp).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <omp.h>

#include <CLI/CLI.hpp>

#include "stability_map.hpp"
#include "io/provenance.hpp"
#include "scene/run_scene.hpp"

int main(int argc, char** argv) {
  namespace sm = rbc::stability_map;
  bool quick = false, check = false, p_reuse = false;
  std::string out;
  int threads = 0;
  CLI::App app{"stability_map: largest stable time step of the explicit and semi-implicit couplings"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("stability_map"), "print the code id and commit this program was built from");
  app.add_option("--out", out, "output folder (default results/stability_map)");
  app.add_flag("--quick", quick, "a small map (h = 0.5, 0.25 um; three stiffnesses)");
  app.add_flag("--check", check, "exit 1 if an extreme case stopped (the study publishes no numbers for this map)");
  app.add_flag("--reuse", p_reuse, "read the cases finished in the output folder instead of computing them again");
  bool p_resume = false, p_collect = false;
  app.add_flag("--resume", p_resume, "after a stop (Ctrl-C, SIGTERM): keep the cases already written, compute the rest");
  app.add_flag("--collect", p_collect, "read the cases finished in the output folder and compute none (the others: not run)");
  bool study_only = false;
  app.add_flag("--study-only", study_only,
               "the map make reproduce draws: h = 0.5 and 0.25 um, every stiffness and extreme case (without it h = 0.125 um too)");
  bool list = false;
  std::string only;
  app.add_flag("--list-cases", list, "print the cases' names (the extreme cases, then one per point), one per line (for GNU parallel)");
  app.add_option("--only", only, "compute this case only (a name from --list-cases), no table");
  app.add_option("--threads", threads, rbc::kThreadsHelp)->check(CLI::Range(0, 256));
  bool record = false;
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/stability_map_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  sm::Params p = quick ? sm::Params::quick_params() : study_only ? sm::Params::report_params() : sm::Params{};
  if (!out.empty()) p.out_dir = out;
  p.reuse = p_reuse;
  p.resume = p_resume;
  p.collect = p_collect;
  p.only = only;
  if (list) {
    for (const std::string& c : sm::cases(p)) std::printf("%s\n", c.c_str());
    return 0;
  }
  if (check && !only.empty()) {
    std::fprintf(stderr, "stability_map: error: --check judges the whole map: drop --only (add --reuse after computing the cases)\n");
    return 2;
  }
  omp_set_num_threads(threads > 0 ? threads : rbc::default_threads());
  try {
    const sm::Results r = sm::run(p);
    if (!only.empty()) return 0;
    if (record && !r.not_run.empty()) {
      std::fprintf(stderr, "stability_map: error: --record-regression with %zu cases not run (--collect): the record would lose them\n",
                   r.not_run.size());
      return 2;
    }
    int unstable_extremes = 0;
    for (const auto& e : r.extremes) unstable_extremes += !e.stable;
    std::printf("stability map: %zu points, %d of %zu extreme cases stopped; outputs in %s\n", r.points.size(), unstable_extremes,
                r.extremes.size(), p.out_dir.c_str());
    const int extremes = check && unstable_extremes > 0 ? 1 : 0;
    return std::max(extremes, rbc::handle_quick_record("stability_map", r.quick_record, quick, record, check, p.out_dir, std::cout));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stability_map: %s\n", e.what());
    return 2;
  }
}
