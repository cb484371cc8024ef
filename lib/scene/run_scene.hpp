#pragma once
// Runs a scene to its end and writes its outputs into the output folder, in SI units throughout
// (lengths in m), each file stating them in its header:
//   summary.json  steps, t_end, wall_seconds, mean_velocity, reynolds, nodal_mean_velocity, hematocrit, cells, disks, …
//   series.csv    "# units: s,m/s,…" (one unit per column; 1 for a pure number), the names, then
//                 one row per sample: t, mean_velocity, reynolds, hematocrit, max_speed, cg_iterations,
//                 coupling_iterations, nodal_mean_velocity (U_n, averaged over the sample interval as
//                 mean_velocity is), with cells plasma_flux_velocity and plasma_open_velocity (the
//                 plasma alone at that instant: diagnostics/flow_diagnostics.hpp) and the wall gaps, with
//                 obstacles the parts' velocities (flux over the open height, and the nodal mean over
//                 the passage: fictitious_domain/obstacles.hpp), then per cell k: cellk_x, cellk_y,
//                 cellk_area, cellk_perimeter, cellk_area_drift, cellk_max_strain
//   snapshots.dat membrane nodes (x1, x2 in m) at the [output] snapshots times (gnuplot: one index per time)
//   frames.dat    the movie's frames when [output] frames > 0 (scene/movie_frames.hpp)
//   membranes_final.dat  the membranes at the end
//   profile.csv   "# units: m,m/s,m/s", then y, x1-averaged u1 and u2 at the end
//   field_<k>.dat the velocity field at snapshot k when [output] fields = true: x, y (m), |u|, u1, u2 (m/s)
//   vtk/          ParaView files (fluid, membranes, disks, obstacles, run.pvd) when [output] vtk = true:
//                 scene/vtk_output.hpp
#include <functional>
#include <optional>
#include <string>

#include "scene/simulation.hpp"

namespace rbc {

struct RunOptions {
  std::string out_dir;    // created if missing
  int threads = 0;        // 0: default_threads()
  bool progress = true;   // progress line on stderr
  std::string label = "rbcflow";  // names the run on the progress line
  // Checkpoints (out_dir/checkpoint.bin, the one before as checkpoint.bin.prev): every
  // checkpoint_wall seconds of wall-clock time and every checkpoint_sim seconds of simulated
  // time (0: not on that clock), and on SIGINT or SIGTERM, after which the run stops
  // (RunInterrupted). Only states that passed the health checks are written.
  double checkpoint_wall = 600;  // s
  double checkpoint_sim = 0;     // s
  // Continue from the newest usable checkpoint in out_dir instead of starting afresh: whole, of
  // this scene and this code, its outputs as long as it recorded (checkpoint.bin, else
  // checkpoint.bin.prev with the reason printed; CheckpointError where neither is usable).
  bool resume = false;
  // Resume a checkpoint written by other code (named on stderr) instead of refusing it.
  bool any_code = false;
  // A fresh run into a folder that holds another run's files (its checkpoints, series, summary,
  // snapshots, frames, fields, VTK): they are cleared first, so that no file of the old run stays
  // beside the new one; with refuse_other_run (rbcflow run without --overwrite) the run is refused
  // instead (SceneError naming the folder). Either way the folder is locked for the run's life
  // (DIR/.lock, flock): a second process on it stops at once (OutputError).
  bool refuse_other_run = false;
  // Called after every completed step (tests use it to interrupt a run at a chosen step).
  std::function<void(long step)> after_step = nullptr;
};

// An output file could not be written (a full disk, a removed folder): the run stops at once,
// its last checkpoint kept (resume once there is room).
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A run stopped by SIGINT or SIGTERM after writing its checkpoint.
struct RunInterrupted : std::runtime_error {
  RunInterrupted(const std::string& what, int signal) : std::runtime_error(what), signal(signal) {}
  int signal;
};

struct RunSummary {
  long steps = 0;
  double t_end = 0, wall_seconds = 0;
  double mean_velocity = 0, reynolds = 0, max_speed = 0;  // mean velocity: averaged over the last sample interval
  double nodal_mean_velocity = 0;  // m/s, the nodal mean U_n (diagnostics/flow_diagnostics.hpp), averaged alike
  double hematocrit = 0;                                  // %
  std::vector<CellState> cells;
};

// Throws SceneError (output folder not writable), RunFailure (instability; series.csv holds
// every sample up to the failure and the last checkpoint is kept), RunInterrupted (a signal;
// checkpoint written) or CheckpointError (resume: no usable checkpoint of this scene).
RunSummary run_scene(const Scene& scene, const RunOptions& options);

// The summary of a finished run of this scene in dir (summary.json naming the same scene source,
// Δt, coupling and end time) made by this code (its "code": io/provenance.hpp), or nothing. With
// any_code, a run of other code is read too: the evidence kept in the repository, each run named
// with its code by the caller (paper/keep_evidence.sh).
std::optional<RunSummary> read_finished_run(const std::string& dir, const Scene& scene, bool any_code = false);

// Whether dir holds a checkpoint to resume from (checkpoint.bin or checkpoint.bin.prev).
bool has_checkpoint(const std::string& dir);

// The scene the newest usable checkpoint of dir was written for (rbcflow resume DIR); throws
// CheckpointError. any_code: as RunOptions::any_code.
Scene checkpoint_scene(const std::string& dir, bool any_code = false);

// The state of the newest checkpoint in dir loaded into sim, which must be built from
// checkpoint_scene(dir) (for measurements that start mid-run, e.g. bench_channel --crowd-from);
// throws CheckpointError.
void load_checkpoint(const std::string& dir, Simulation& sim);

// The OpenMP threads of a program not told (--threads 0): a Slurm task's SLURM_CPUS_PER_TASK; one
// under a job pool that runs a process per core (GNU parallel: PARALLEL_SEQ; a Slurm array:
// SLURM_ARRAY_TASK_ID); OpenMP's own default (OMP_NUM_THREADS, else every core) otherwise.
int default_threads();
// The --threads help of every program, saying the above.
inline constexpr const char* kThreadsHelp =
    "OpenMP threads (default 0: SLURM_CPUS_PER_TASK in a Slurm job, 1 under GNU parallel or a Slurm array, else "
    "OMP_NUM_THREADS or every core)";

// Creates dir (and parents) and checks that a file can be written in it; throws SceneError.
void prepare_output_dir(const std::string& dir);

}  // namespace rbc
