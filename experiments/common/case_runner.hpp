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
//   num            a number written back exactly (%.17g) into a scene override;
//   run_selected   runs an experiment's cases (or only the one --only names) one after the other.
#include <algorithm>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
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

// Runs every case of `all` (or only the one named `only`; an unknown name is an error pointing to
// the experiment's --list-cases) with run_case, after creating out_dir; the results by case name.
template <class Case, class RunCase>
auto run_selected(std::vector<Case> all, const std::string& only, const std::string& experiment, const std::string& out_dir,
                  RunCase run_case) {
  if (!only.empty()) {
    std::erase_if(all, [&](const Case& c) { return c.name != only; });
    if (all.empty()) throw std::invalid_argument("--only " + only + ": no such case (build/bin/" + experiment + " --list-cases lists them)");
  }
  std::filesystem::create_directories(out_dir);
  std::map<std::string, decltype(run_case(all.front()))> results;
  for (const Case& c : all) results[c.name] = run_case(c);
  return results;
}

}  // namespace rbc::case_runner
