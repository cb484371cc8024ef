// single_cell_migration: one cell in the study's narrow and wide channels (see the header).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "common/case_runner.hpp"
#include "single_cell_migration.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  namespace scm = rbc::single_cell_migration;
  bool quick = false, check = false;
  std::string out;
  int threads = 0;
  CLI::App app{"single_cell_migration: Figures 3-5 of Shi, Pan & Glowinski (2012)"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("single_cell_migration"), "print the code id and commit this program was built from");
  app.add_option("--out", out, "output folder (default results/single_cell_migration)");
  app.add_flag("--quick", quick, "short CI parameters (h = 0.25 um, to 1 ms)");
  app.add_flag("--check", check, "compare with reference-data/single_cell_migration.csv; exit 1 on a failed row");
  app.add_option("--threads", threads, std::string(rbc::kThreadsHelp) + "; the cases one after the other")
      ->check(CLI::Range(0, 256));
  std::string only;
  bool reuse = false;
  app.add_option("--only", only, "run only this case (a name from --list-cases), or the cases whose name starts with this (e.g. wide, narrow_si)");
  bool list = false;
  app.add_flag("--list-cases", list, "print the cases' names, one per line, the longest first (for GNU parallel)");
  app.add_flag("--reuse", reuse, "read cases whose output folder holds a finished run of the same scene instead of rerunning");
  bool collect = false;
  app.add_flag("--collect", collect, "read back the cases finished in the output folder and run none (a sweep still going: the table so far)");
  bool study_only = false;
  app.add_flag("--study-only", study_only,
               "the study's runs (narrow and wide channels) and the error against run time, no other evidence runs: u_num as recorded in "
               "reference-data/uncertainty/ (make reproduce)");
  bool resume = false;
  app.add_flag("--resume", resume, "continue cases stopped by SIGINT/SIGTERM from the checkpoint in their folder");
  bool record = false;
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/single_cell_migration_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  scm::Params p;
  if (quick) p = scm::Params::quick_params();
  p.only = only;
  p.reuse = reuse;
  p.collect = collect;
  p.resume = resume;
  p.study_only = study_only;
  if (!out.empty()) p.out_dir = out;
  p.threads = threads;
  try {
    if (list) {
      for (const auto& name : scm::case_names(p)) std::printf("%s\n", name.c_str());
      return 0;
    }
    const scm::Results r = scm::run(p);
    std::ofstream cases(p.out_dir + "/cases.csv");
    cases << "case,swelling_ratio,units,steps,wall_seconds,reynolds,hematocrit,y_end_um,time_to_centreline_ms,shape,area_drift\n";
    for (const auto& [name, c] : r.cases) {
      if (!c.failure.empty()) {
        const bool not_run = c.failure == rbc::case_runner::kNotRun;
        std::printf("%-22s %s: %s\n", name.c_str(), not_run ? "not run" : "FAILED", c.failure.c_str());
        cases << name << "," << c.swelling_ratio << "," << c.units << "," << (not_run ? "not run" : "failed") << ",,,,,,,\n";
        continue;
      }
      const auto& cell = c.summary.cells.at(0);
      cases << name << "," << c.swelling_ratio << "," << c.units << "," << c.summary.steps << "," << c.summary.wall_seconds << ","
            << c.summary.reynolds << "," << c.summary.hematocrit << "," << cell.centroid.y() * 1e6 << ","
            << (c.time_to_centreline < 0 ? -1 : c.time_to_centreline * 1e3) << "," << cell.shape.kind << "," << cell.area_drift << "\n";
      std::printf("%-22s %8ld steps %7.1f s  Re %.4f  Hct %.3f %%  y_end %.3f um  shape %-9s area drift %.2e\n", name.c_str(),
                  c.summary.steps, c.summary.wall_seconds, c.summary.reynolds, c.summary.hematocrit, cell.centroid.y() * 1e6,
                  cell.shape.kind.c_str(), cell.area_drift);
    }
    if (!r.units_evidence.empty()) std::ofstream(p.out_dir + "/units_evidence.md") << r.units_evidence;
    if (check && !p.only.empty())
      throw std::invalid_argument("--check compares the whole experiment: drop --only (or add --reuse after running the parts)");
    const int study = check ? rbc::run_reference_check("single_cell_migration", r.measured, p.out_dir, std::cout, !quick) : 0;
    if (record && std::any_of(r.cases.begin(), r.cases.end(), [](const auto& kv) { return kv.second.failure == rbc::case_runner::kNotRun; })) {
      std::fprintf(stderr, "single_cell_migration: error: --record-regression with cases not run (--collect): the record would lose them\n");
      return 2;
    }
    return std::max(study, rbc::handle_quick_record("single_cell_migration", r.quick_record, quick, record, check, p.out_dir, std::cout));
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "single_cell_migration: %s\n", e.what());
    return 2;
  }
}
