#pragma once
// Experiment channel_flow — the cell-free plasma flow every experiment of the study stands on.
//
// Claim: driven by f_p = 12 μ U0 / H² with U0 = Re0 μ / (ρ H), the study's narrow (20 × 10 µm,
// h = 0.125 µm, Re0 = 0.5556) and wide (100 × 50 µm, h = 0.3125 µm, Re0 = 2.778) channels start
// from rest and settle on plane Poiseuille flow with mean velocity U0 = 6.667 cm/s (Shi, Pan &
// Glowinski 2012, DOI 10.1002/fld.2455, the Re0 of its Sections 3.1.1-3.1.3). We check the
// mean velocity and Re against reference-data/channel_flow.csv and plot the start-up against the
// Fourier-series solution and the final profile against the parabola.
//
// Run:  build/bin/channel_flow --check          (both channels, then the comparison)
//       build/bin/channel_flow --quick --check  (larger Δt)
//       build/bin/channel_flow --list-cases | parallel build/bin/channel_flow --only {}; build/bin/channel_flow --reuse --check
#include <map>
#include <string>
#include <vector>

#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "scene/run_scene.hpp"

namespace rbc::channel_flow {

struct Params {
  std::string out_dir = "results/channel_flow";
  bool quick = false;  // Δt raised to 80-96 % of the advective bound (the steady state is Δt-independent)
  int threads = 0;
  bool progress = true;
  bool resume = false;  // a channel whose folder holds a checkpoint (SIGINT/SIGTERM) continues from it
  bool reuse = false;   // a channel finished in its folder (same scene, this code) is read back, not rerun
  std::string only;     // run only this channel (a name of cases())
};

// The cases, one per channel, each run in out_dir/<name> (--list-cases, --only NAME: GNU parallel
// or a Slurm array run them apart; --reuse --check then collects them).
std::vector<std::string> cases();

struct ChannelResult {
  RunSummary summary;
  double profile_error = 0;  // max |u1 − parabola| / peak at the end
  double startup_error = 0;  // max |U(t) − U_exact(t)| / U0 over the samples
};

struct Results {
  std::map<std::string, ChannelResult> channels;  // "narrow", "wide"
  std::map<std::string, Measured> measured;       // ids of reference-data/channel_flow.csv
  std::map<std::string, Observed> quick_record;   // quick runs: for reference-data/regression/channel_flow_quick.csv
};

Results run(const Params& params);

}  // namespace rbc::channel_flow
