#pragma once
// Runs a scene to its end and writes the outputs of SPEC section 8 into the output folder:
//   summary.json  steps, t_end, wall_seconds, mean_velocity, reynolds, hematocrit, cells, disks, …
//   series.csv    one row per sample: t, mean_velocity, reynolds, hematocrit, max_speed, cg_iterations,
//                 then per cell k: cellk_x, cellk_y, cellk_area, cellk_perimeter, cellk_area_drift, cellk_max_strain
//   snapshots.dat membrane nodes at the [output] snapshots times (gnuplot: one index per time)
//   membranes_final.dat  the membranes at the end
//   profile.csv   y, x1-averaged u1 and u2 at the end (m, m/s)
//   vtk/          ParaView files of the velocity, when [output] vtk = true
#include <optional>
#include <string>

#include "scene/simulation.hpp"

namespace rbc {

struct RunOptions {
  std::string out_dir;    // created if missing
  int threads = 0;        // 0: the OpenMP default
  bool progress = true;   // progress line on stderr
  std::string label = "rbcflow";  // names the run on the progress line
};

struct RunSummary {
  long steps = 0;
  double t_end = 0, wall_seconds = 0;
  double mean_velocity = 0, reynolds = 0, max_speed = 0;  // mean velocity: averaged over the last sample interval
  double hematocrit = 0;                                  // %
  std::vector<CellState> cells;
};

// Throws SceneError (output folder not writable) or RunFailure (instability); in the latter case
// series.csv holds every sample up to the failure.
RunSummary run_scene(const Scene& scene, const RunOptions& options);

// The summary of a finished run of this scene in dir (summary.json naming the same scene source,
// Δt, coupling and end time), or nothing.
std::optional<RunSummary> read_finished_run(const std::string& dir, const Scene& scene);

// Creates dir (and parents) and checks that a file can be written in it; throws SceneError.
void prepare_output_dir(const std::string& dir);

}  // namespace rbc
