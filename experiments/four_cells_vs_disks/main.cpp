// four_cells_vs_disks: four cells of increasing bending stiffness against four rigid disks (see
// four_cells_vs_disks.hpp).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "four_cells_vs_disks.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  rbc::four_cells_vs_disks::Params p;
  bool check = false, record = false, list = false, no_convergence = false, no_evidence = false;
  CLI::App app{"four_cells_vs_disks: four cells (k_b ... 1000 k_b, s* = 0.7) against four rigid disks in the wide channel"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("four_cells_vs_disks"), "print the code id and commit this program was built from");
  std::string out;
  app.add_option("--out", out, "output folder (default results/four_cells_vs_disks, with --quick results/four_cells_vs_disks_quick)");
  app.add_flag("--quick", p.quick, "short CI parameters (5 ms, h = 0.625 um)");
  app.add_flag("--check", check, "compare with reference-data/four_cells_vs_disks.csv; exit 1 on a failed row");
  app.add_flag("--list-cases", list, "print the cases' names, one per line, the longest first (for GNU parallel)");
  app.add_option("--only", p.only, "run this case only (a name from --list-cases), no comparison");
  app.add_option("--threads", p.threads, rbc::kThreadsHelp)->check(CLI::Range(0, 256));
  app.add_flag("--resume", p.resume, "continue cases stopped by SIGINT/SIGTERM from their checkpoints");
  app.add_flag("--reuse", p.reuse, "read the cases finished in the output folder instead of running them again");
  app.add_flag("--collect", p.collect, "read back the cases finished in the output folder and run none (a sweep still going: the table so far)");
  app.add_flag("--no-convergence", no_convergence, "skip the 1.2 ms error-against-run-time runs");
  app.add_flag("--study-only", p.study_only,
               "the runs the study's rows report (each case's finest dt), no evidence runs: u_num as recorded in reference-data/uncertainty/ (make reproduce)");
  app.add_flag("--no-evidence", no_evidence, "skip the full runs with dt halved and h doubled");
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/four_cells_vs_disks_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  p.convergence = !no_convergence;
  p.evidence = !no_evidence;
  if (p.quick) p.out_dir = "results/four_cells_vs_disks_quick";
  if (!out.empty()) p.out_dir = out;
  try {
    if (list) {
      for (const auto& c : rbc::four_cells_vs_disks::cases(p)) std::printf("%s\n", c.name.c_str());
      return 0;
    }
    if (check && !p.only.empty()) throw std::invalid_argument("--check compares the whole experiment: drop --only (add --reuse after running the cases)");
    const auto r = rbc::four_cells_vs_disks::run(p);
    for (const auto& [name, c] : r.cases)
      if (c.spec.role == "study" || c.spec.role == "ensemble" || !p.only.empty())
        std::printf("four_cells_vs_disks %-12s %6ld steps, %7.1f s wall; %s %.4f%s, Re %.4f%s%s\n", name.c_str(), c.summary.steps,
                    c.summary.wall_seconds, c.spec.role == "validation" ? "x2 / W" : "distance", c.distance * (c.spec.role == "validation" ? 1.0 : 1e6),
                    c.spec.role == "validation" ? "" : " um", c.reynolds, c.failure.empty() ? "" : "; STOPPED: ", c.failure.c_str());
    if (!p.only.empty()) return r.cases.begin()->second.failure.empty() ? 0 : 3;
    std::cout << "\n" << r.spread_md;
    const int study = check ? rbc::run_reference_check("four_cells_vs_disks", r.measured, p.out_dir, std::cout, !p.quick) : 0;
    // Our disk against published data (reference-data/disk_validation.csv), its own table.
    const int validation = check && !p.quick && !p.study_only ? rbc::run_reference_check("disk_validation", r.validation, p.out_dir + "/validation", std::cout) : 0;
    return std::max({study, validation, rbc::handle_quick_record("four_cells_vs_disks", r.quick_record, p.quick, record, check, p.out_dir, std::cout)});
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "four_cells_vs_disks: %s; continue with the same command and --resume\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "four_cells_vs_disks: error: %s\n", e.what());
    return 2;
  }
}
