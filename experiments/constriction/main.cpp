// constriction: 12 cells through the study's 15 um passage (see constriction.hpp).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "constriction.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  rbc::constriction::Params p;
  bool check = false, record = false;
  CLI::App app{"constriction: 12 cells through a channel with a constriction, blocks held by the fictitious domain"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("constriction"), "print the code id and commit this program was built from");
  std::string out;
  app.add_option("--out", out, "output folder (default results/constriction, with --quick results/constriction_quick)");
  app.add_flag("--quick", p.quick, "short CI parameters (2 ms, h = 0.625 um)");
  app.add_flag("--check", check, "compare with reference-data/constriction.csv; exit 1 on a failed row");
  app.add_option("--threads", p.threads, rbc::kThreadsHelp)->check(CLI::Range(0, 256));
  app.add_flag("--resume", p.resume, "continue a run stopped by SIGINT/SIGTERM from its checkpoint");
  bool no_convergence = false;
  app.add_flag("--no-convergence", no_convergence, "skip the convergence study (short runs over h and dt, both couplings)");
  bool study_only = false;
  app.add_flag("--study-only", study_only,
               "the study's run and the convergence study on the coarse meshes (h >= 0.625 um): u_num's Δt part as recorded in reference-data/uncertainty/ (make reproduce)");
  app.add_flag("--reuse", p.reuse, "read the finished runs in the output folder instead of running them again");
  bool list = false;
  app.add_flag("--list-cases", list, "print the cases' names (the experiment's run, then the convergence study's), one per line (for GNU parallel)");
  app.add_option("--only", p.only, "run this case only (a name from --list-cases), no comparison");
  app.add_flag("--collect", p.collect, "read back the finished runs in the output folder and run none (a run not finished: its rows not run)");
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/constriction_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  p.convergence = !no_convergence;
  p.coarse_convergence = study_only;
  // An explicit --out wins (make reproduce QUICK=1 passes results/constriction and draws from it).
  if (p.quick) p.out_dir = "results/constriction_quick";
  if (!out.empty()) p.out_dir = out;
  try {
    if (list) {
      for (const std::string& c : rbc::constriction::cases(p)) std::printf("%s\n", c.c_str());
      return 0;
    }
    if (check && !p.only.empty()) throw std::invalid_argument("--check compares the whole experiment: drop --only (add --reuse after running the cases)");
    const auto r = rbc::constriction::run(p);
    if (!p.only.empty()) return 0;
    if (r.collected_without_run)
      std::printf("constriction: --collect: no finished run of today's scene in %s/run: its rows not run\n", p.out_dir.c_str());
    else
      std::printf("constriction: %ld steps to %.4g s in %.1f s wall; U_wide = %.4f cm/s, U_narrow = %.4f cm/s (ratio %.4f), "
                "Re %.4f / %.4f; Hct %.4f %%\n",
                r.summary.steps, r.summary.t_end, r.summary.wall_seconds, r.u_wide * 100, r.u_narrow * 100, r.u_narrow / r.u_wide,
                r.re_wide, r.re_narrow, r.hematocrit);
    const int study = check ? rbc::run_reference_check("constriction", r.measured, p.out_dir, std::cout, !p.quick) : 0;
    if (r.collected_without_run) {  // no quick record to check or write: its rows are not run
      if (record) {
        std::fprintf(stderr, "constriction: error: --record-regression with the run not run (--collect): the record would lose it\n");
        return 2;
      }
      return study;
    }
    return std::max(study, rbc::handle_quick_record("constriction", r.quick_record, p.quick, record, check, p.out_dir, std::cout));
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "constriction: %s; continue with the same command and --resume\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "constriction: error: %s\n", e.what());
    return 2;
  }
}
