// cell_free_layer: 50 and 100 cells and the plasma layer next to the walls (see cell_free_layer.hpp).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cell_free_layer.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  rbc::cell_free_layer::Params p;
  bool check = false, record = false, list = false, no_evidence = false, no_convergence = false;
  CLI::App app{"cell_free_layer: 50 and 100 cells (s* = 0.7) in the wide channel and the cell-free layer next to the walls"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("cell_free_layer"), "print the code id and commit this program was built from");
  std::string out;
  app.add_option("--out", out, "output folder (default results/cell_free_layer, with --quick results/cell_free_layer_quick)");
  app.add_flag("--quick", p.quick, "short CI parameters (3 ms, h = 0.625 um)");
  app.add_flag("--check", check, "compare with reference-data/cell_free_layer.csv; exit 1 on a failed row");
  app.add_flag("--list-cases", list, "print the cases' names, one per line, the longest first (for GNU parallel)");
  bool list_read = false;
  app.add_flag("--list-read-only", list_read,
               "print the cases read where finished or kept but never run (with --study-only: the arrangements the rows are judged by)");
  app.add_option("--only", p.only, "run this case only (a name from --list-cases), no comparison");
  app.add_option("--threads", p.threads, rbc::kThreadsHelp)->check(CLI::Range(0, 256));
  app.add_flag("--resume", p.resume, "continue cases stopped by SIGINT/SIGTERM from their checkpoints");
  app.add_flag("--reuse", p.reuse, "read the cases finished in the output folder instead of running them again");
  app.add_flag("--collect", p.collect, "read back the cases finished in the output folder and run none (a sweep still going: the table so far)");
  app.add_flag("--study-only", p.study_only,
               "the runs the study's rows report (dt = 1.5 us), no evidence runs: u_num as recorded in reference-data/uncertainty/ (make reproduce)");
  app.add_flag("--no-evidence", no_evidence, "skip the runs with dt halved and h doubled");
  app.add_flag("--no-convergence", no_convergence, "skip the 1.2 ms error-against-run-time runs");
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/cell_free_layer_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  p.evidence = !no_evidence;
  p.convergence = !no_convergence;
  if (p.quick) p.out_dir = "results/cell_free_layer_quick";
  if (!out.empty()) p.out_dir = out;
  try {
    if (list || list_read) {
      for (const auto& c : rbc::cell_free_layer::cases(p))
        if (c.read_only == list_read) std::printf("%s\n", c.name.c_str());
      return 0;
    }
    if (check && !p.only.empty()) throw std::invalid_argument("--check compares the whole experiment: drop --only (add --reuse after running the cases)");
    const auto r = rbc::cell_free_layer::run(p);
    for (const auto& [name, c] : r.cases)
      std::printf("cell_free_layer %-14s %6ld steps, %7.1f s wall; layer %.3f um (walls %.3f, %.3f), Hct %.2f %%, Re %.4f%s%s\n", name.c_str(),
                  c.summary.steps, c.summary.wall_seconds, c.layer * 1e6, c.layer_lower * 1e6, c.layer_upper * 1e6, c.hct, c.re,
                  c.failure.empty() ? "" : "; STOPPED: ", c.failure.c_str());
    if (!p.only.empty()) return r.cases.begin()->second.failure.empty() ? 0 : 3;
    if (!r.ensemble_md.empty()) std::cout << "\n" << r.ensemble_md;
    const int study = check ? rbc::run_reference_check("cell_free_layer", r.measured, p.out_dir, std::cout, !p.quick) : 0;
    return std::max(study, rbc::handle_quick_record("cell_free_layer", r.quick_record, p.quick, record, check, p.out_dir, std::cout));
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "cell_free_layer: %s; continue with the same command and --resume\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cell_free_layer: error: %s\n", e.what());
    return 2;
  }
}
