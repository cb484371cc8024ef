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
  bool list = false;
  app.add_flag("--list-cases", list, "print the cases' names (the channels), one per line (for GNU parallel)");
  app.add_option("--only", p.only, "run this case only (a name from --list-cases), no comparison");
  app.add_option("--threads", p.threads, rbc::kThreadsHelp)->check(CLI::Range(0, 256));
  app.add_flag("--resume", p.resume, "continue a channel stopped by SIGINT/SIGTERM from the checkpoint in its folder");
  app.add_flag("--reuse", p.reuse, "read the channels finished in the output folder instead of running them again");
  bool record = false;
  app.add_flag("--record-regression", record,
               "with --quick: write this run's numbers into reference-data/regression/channel_flow_quick.csv (keeps the bands)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (list) {
      for (const std::string& c : rbc::channel_flow::cases()) std::printf("%s\n", c.c_str());
      return 0;
    }
    if (check && !p.only.empty()) throw std::invalid_argument("--check compares the whole experiment: drop --only (add --reuse after running the cases)");
    const auto res = rbc::channel_flow::run(p);
    for (const auto& [name, r] : res.channels)
      std::printf("%-6s: %ld steps, %.1f s wall; max |u1 - parabola|/peak = %.2e; start-up max |U - U_exact|/U0 = %.2e\n",
                  name.c_str(), r.summary.steps, r.summary.wall_seconds, r.profile_error, r.startup_error);
    if (!p.only.empty()) return 0;
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
