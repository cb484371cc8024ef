#pragma once
// What the experiments made of independent cases share (issue 17, item 4): every case is one
// scene run in its own folder, so that GNU parallel or a Slurm array can run the cases anywhere
// (--list-cases, --only NAME) and the experiment collects them afterwards (--check --reuse).
//
//   run_or_reuse   runs the case's scene into its folder, or with reuse reads back the finished
//                  run of the same scene (summary.json) or the failure it stopped with
//                  (failure.txt: the scene's source, its Δt, then why), so that a collecting
//                  --check --reuse neither reruns a finished case nor a failed one;
//   window_mean    the mean of a sampled series over t ≥ from (the rows' "last millisecond");
//   symmetric_unit a uniform number in [−1, 1) from a Mersenne twister's raw 32-bit output (the
//                  same on every platform, unlike std::uniform_real_distribution): the ensembles'
//                  perturbed starts;
//   num            a number written back exactly (%.17g) into a scene override.
#include <random>
#include <string>
#include <vector>

#include "scene/run_scene.hpp"

namespace rbc::case_runner {

struct CaseRun {
  RunSummary summary;
  std::string failure;  // why the run stopped (one line; empty: it reached its end)
};

struct CaseRunOptions {
  int threads = 0;
  bool progress = true;
  bool resume = false;  // continue from the folder's checkpoint, if there is one
  bool reuse = false;   // read a finished (or failed) run of the same scene back
  std::string label;    // the progress line's name
};

// Throws what run_scene throws except RunFailure (returned as the failure).
CaseRun run_or_reuse(const Scene& scene, const std::string& out_dir, const CaseRunOptions& o);

double window_mean(const std::vector<double>& t, const std::vector<double>& v, double from);
double symmetric_unit(std::mt19937& g);
std::string num(double v);

}  // namespace rbc::case_runner
