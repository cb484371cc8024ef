// channel_flow: cell-free Poiseuille flow in the study's channels (see channel_flow.hpp).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "channel_flow.hpp"
#include "io/provenance.hpp"

int main(int argc, char** argv) {
  rbc::channel_flow::Params p;
  bool check = false;
  CLI::App app{"channel_flow: the study's cell-free channels against plane Poiseuille flow"};
  rbc::set_command_line(argc, argv);
  app.set_version_flag("--version", rbc::version_line("channel_flow"), "print the code id and commit this program was built from");
  app.add_option("--out", p.out_dir, "output folder");
  app.add_flag("--quick", p.quick, "short CI parameters");
  app.add_flag("--check", check, "compare with reference-data/channel_flow.csv; exit 1 on a failed row");
  app.add_option("--threads", p.threads, "OpenMP threads")->check(CLI::Range(1, 256));
  app.add_flag("--resume", p.resume, "continue a channel stopped by SIGINT/SIGTERM from the checkpoint in its folder");
  bool record = false;
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/channel_flow_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto res = rbc::channel_flow::run(p);
    for (const auto& [name, r] : res.channels)
      std::printf("%-6s: %ld steps, %.1f s wall; max |u1 - parabola|/peak = %.2e; start-up max |U - U_exact|/U0 = %.2e\n",
                  name.c_str(), r.summary.steps, r.summary.wall_seconds, r.profile_error, r.startup_error);
    const int study = check ? rbc::run_reference_check("channel_flow", res.measured, p.out_dir, std::cout) : 0;
    return std::max(study, rbc::handle_quick_record("channel_flow", res.quick_record, p.quick, record, check, p.out_dir, std::cout));
  } catch (const rbc::RunInterrupted& e) {
    std::fprintf(stderr, "channel_flow: %s; continue with the same command and --resume\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "channel_flow: error: %s\n", e.what());
    return 2;
  }
}
