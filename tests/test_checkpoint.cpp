// Checkpoints: a damaged file is refused, a run stopped by SIGTERM and resumed gives bit for bit
// the series and summary of the run that went straight through, a newest checkpoint that cannot
// continue the run gives way to the previous one, and a checkpoint of another scene or code is
// refused with what differs. (Killed at random instants: tests/kill_resume.sh.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "io/checkpoint.hpp"
#include "io/provenance.hpp"
#include "io/progress.hpp"
#include "scene/run_scene.hpp"

namespace rbc {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// An empty record reads back empty (make fuzz found the reader handing memcpy the null data() of an
// empty vector: undefined behaviour the sanitized build of this test reports).
TEST(CheckpointFile, EmptyRecordsReadBackEmpty) {
  const fs::path path = fs::temp_directory_path() / "rbcflow_ckpt_empty_records.bin";
  CheckpointWriter w;
  w.put(std::vector<double>{});
  w.put(std::string());
  w.put(Eigen::VectorXd());
  w.commit(path.string());
  CheckpointReader r(path.string());
  EXPECT_TRUE(r.get_doubles().empty());
  EXPECT_TRUE(r.get_string().empty());
  EXPECT_EQ(r.get_vector().size(), 0);
  EXPECT_TRUE(r.at_end());
}

TEST(CheckpointFile, RoundTripsAndRefusesDamagedFiles) {
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_file";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "c.bin").string();
  CheckpointWriter w;
  w.put(std::string("scene text"));
  w.put(std::vector<double>{1.5, -2.0, 3e-300});
  w.put(std::int64_t(-7));
  w.put(0.1);
  w.commit(path);
  {
    CheckpointReader r(path);
    EXPECT_EQ(r.get_string(), "scene text");
    EXPECT_EQ(r.get_doubles(), (std::vector<double>{1.5, -2.0, 3e-300}));
    EXPECT_EQ(r.get_int(), -7);
    EXPECT_EQ(r.get_double(), 0.1);
    EXPECT_TRUE(r.at_end());
    EXPECT_NE(error_of([&] { r.get_double(); }).find("ends too early"), std::string::npos);
  }
  // A second commit keeps the first as .prev (the same bytes) and leaves no temporary file.
  const std::string first = read_all(path);
  w.commit(path);
  EXPECT_TRUE(fs::exists(path + ".prev"));
  EXPECT_EQ(read_all(path + ".prev"), first);
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  // A full disk (the device that is always full): the write fails naming the file and the
  // reason, and the checkpoint in place stays whole.
  EXPECT_NE(error_of([&] { write_synced("/dev/full", first.data(), first.size()); }).find("No space left on device"), std::string::npos);
  std::string bytes = read_all(path);
  auto write = [&](const std::string& b) { std::ofstream(path, std::ios::binary | std::ios::trunc) << b; };
  std::string flipped = bytes;
  flipped[30] ^= 1;
  write(flipped);
  EXPECT_NE(error_of([&] { CheckpointReader r(path); }).find("checksum mismatch"), std::string::npos);
  write(bytes.substr(0, bytes.size() - 5));
  EXPECT_NE(error_of([&] { CheckpointReader r(path); }).find("checksum mismatch"), std::string::npos);
  write("[channel]\nlength = 1\n");
  EXPECT_NE(error_of([&] { CheckpointReader r(path); }).find("not an rbcflow checkpoint"), std::string::npos);
  write("");
  EXPECT_NE(error_of([&] { CheckpointReader r(path); }).find("not an rbcflow checkpoint"), std::string::npos);
}

// Two cells, semi-implicit (the GMRES start and the preconditioner blocks are state), or one
// cell, explicit; a coarse narrow channel so that the test takes seconds.
Scene two_cell_scene(const std::string& coupling, int cells = 2) {
  Scene s;
  s.source = "test_checkpoint " + coupling;
  s.length = 20e-6;
  s.height = 10e-6;
  s.mesh_size = 0.5e-6;
  s.reynolds0 = 0.5556;
  s.coupling = coupling;
  s.dt = coupling == "explicit" ? 1e-7 : 5e-7;
  s.end = 60 * s.dt;
  s.output_every = 4 * s.dt;
  s.snapshots = {0.0, 30 * s.dt, 60 * s.dt};
  s.frames = 20;  // every 3 steps: frame 7 (step 21) falls between the checkpoint and the stop
  s.cells.push_back({{5e-6, 3e-6}, 0.55, 0.0});
  if (coupling != "explicit" && cells == 2) s.cells.push_back({{14e-6, 6.5e-6}, 0.7, 0.3});
  return s;
}

// The summary less what the clock writes (wall time, start and end instants).
nlohmann::json summary_without_wall_time(const fs::path& dir) {
  nlohmann::json j = nlohmann::json::parse(read_all(dir / "summary.json"));
  for (const char* clock : {"wall_seconds", "started", "ended"}) j.erase(clock);
  return j;
}

void expect_interrupted_equals_straight(const std::string& coupling, int cells, bool disk = false, const std::string& scheme = "lie",
                                        long stop_after = 23) {
  Scene scene = two_cell_scene(coupling, cells);
  if (disk) scene.disks.push_back({{14e-6, 6e-6}, 1.5e-6});  // a rigid disk: its state is in the checkpoint too
  scene.scheme = scheme;  // the extrapolated scheme: its half-step run's warm starts too; BDF2: its history
  if (scheme == "bdf2") scene.projection = "incremental";
  const std::string tag = coupling + std::to_string(cells) + (disk ? "disk" : "") + scheme + std::to_string(stop_after);
  const fs::path straight = fs::temp_directory_path() / ("rbcflow_ckpt_straight_" + tag);
  const fs::path stopped = fs::temp_directory_path() / ("rbcflow_ckpt_stopped_" + tag);
  fs::remove_all(straight);
  fs::remove_all(stopped);
  const int threads = 2;
  // Straight through, with checkpoints on the way (writing them must not change the run).
  run_scene(scene, {.out_dir = straight.string(), .threads = threads, .progress = false, .checkpoint_sim = 10 * scene.dt});
  // Stopped by SIGTERM after step 23 (between two rebuilds of the preconditioner blocks; not on a
  // sample), with a checkpoint from step 10 and 20 already on disk ...
  RunOptions o{.out_dir = stopped.string(), .threads = threads, .progress = false, .checkpoint_sim = 10 * scene.dt};
  o.after_step = [stop_after](long step) {
    if (step == stop_after) std::raise(SIGTERM);
  };
  const std::string message = error_of([&] { run_scene(scene, o); });
  EXPECT_NE(message.find("interrupted by SIGTERM"), std::string::npos) << message;
  EXPECT_NE(message.find("step " + std::to_string(stop_after)), std::string::npos) << message;
  ASSERT_TRUE(fs::exists(stopped / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(stopped / "summary.json"));
  // ... then resumed to the end.
  o.after_step = nullptr;
  o.resume = true;
  run_scene(scene, o);
  EXPECT_EQ(read_all(stopped / "series.csv"), read_all(straight / "series.csv"));
  EXPECT_EQ(read_all(stopped / "snapshots.dat"), read_all(straight / "snapshots.dat"));
  EXPECT_EQ(read_all(stopped / "frames.dat"), read_all(straight / "frames.dat"));
  EXPECT_EQ(summary_without_wall_time(stopped), summary_without_wall_time(straight));
}

TEST(Checkpoint, SemiImplicitTwoCellsInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("semi-implicit", 2);
}

TEST(Checkpoint, SemiImplicitOneCellInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("semi-implicit", 1);
}

TEST(Checkpoint, ExplicitOneCellInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("explicit", 1);
}

TEST(Checkpoint, SemiImplicitCellAndRigidDiskInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("semi-implicit", 1, true);
}

TEST(Checkpoint, ExtrapolatedSchemeCellAndRigidDiskInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("semi-implicit", 1, true, "lie-extrapolated");
}

TEST(Checkpoint, Bdf2SchemeTwoCellsInterruptedBySigtermAndResumedEqualsTheStraightRun) {
  expect_interrupted_equals_straight("semi-implicit", 2, false, "bdf2");
  expect_interrupted_equals_straight("semi-implicit", 2, false, "bdf2", 1);  // after its start: the nodes' history is the start's
}

TEST(Checkpoint, ADamagedNewestCheckpointFallsBackToThePreviousOne) {
  const Scene scene = two_cell_scene("explicit");
  const fs::path straight = fs::temp_directory_path() / "rbcflow_ckpt_fallback_straight";
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_fallback";
  fs::remove_all(straight);
  fs::remove_all(dir);
  run_scene(scene, {.out_dir = straight.string(), .threads = 1, .progress = false});
  RunOptions o{.out_dir = dir.string(), .threads = 1, .progress = false, .checkpoint_sim = 10 * scene.dt};
  o.after_step = [](long step) {
    if (step == 35) std::raise(SIGINT);
  };
  EXPECT_THROW(run_scene(scene, o), RunInterrupted);
  ASSERT_TRUE(fs::exists(dir / "checkpoint.bin.prev"));  // step 30
  {
    std::fstream f(dir / "checkpoint.bin", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x7f');
  }
  o.after_step = nullptr;
  o.resume = true;
  run_scene(scene, o);  // from step 30: the outputs are cut back to that step and continue
  EXPECT_EQ(read_all(dir / "series.csv"), read_all(straight / "series.csv"));
  EXPECT_EQ(summary_without_wall_time(dir), summary_without_wall_time(straight));
}

// A crash of the machine between a checkpoint and the sync of series.csv (or a series cut by hand)
// leaves the series shorter than the newest checkpoint recorded: the previous checkpoint, whose
// series is whole, continues the run (it stopped the resume before).
TEST(Checkpoint, ASeriesShorterThanTheNewestCheckpointExpectsFallsBackToThePreviousOne) {
  const Scene scene = two_cell_scene("explicit");
  const fs::path straight = fs::temp_directory_path() / "rbcflow_ckpt_short_series_straight";
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_short_series";
  fs::remove_all(straight);
  fs::remove_all(dir);
  run_scene(scene, {.out_dir = straight.string(), .threads = 1, .progress = false});
  RunOptions o{.out_dir = dir.string(), .threads = 1, .progress = false, .checkpoint_sim = 10 * scene.dt};
  o.after_step = [](long step) {
    if (step == 35) std::raise(SIGINT);  // checkpoints at steps 30 (.prev) and 35; samples every 4 steps
  };
  EXPECT_THROW(run_scene(scene, o), RunInterrupted);
  ASSERT_TRUE(fs::exists(dir / "checkpoint.bin.prev"));
  {  // the series without its last row (step 32's, written after the checkpoint of step 30)
    const std::string series = read_all(dir / "series.csv");
    const std::size_t last = series.rfind('\n', series.size() - 2);
    ASSERT_NE(last, std::string::npos);
    fs::resize_file(dir / "series.csv", last + 1);
  }
  o.after_step = nullptr;
  o.resume = true;
  testing::internal::CaptureStderr();
  run_scene(scene, o);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("series.csv is shorter"), std::string::npos) << said;
  EXPECT_NE(said.find("resuming from"), std::string::npos) << said;
  EXPECT_EQ(read_all(dir / "series.csv"), read_all(straight / "series.csv"));
  EXPECT_EQ(summary_without_wall_time(dir), summary_without_wall_time(straight));
}

// Only checkpoint.bin.prev left (the newest removed or lost): the folder still holds a checkpoint
// for every program that resumes (the experiments tested for checkpoint.bin alone and started
// afresh).
TEST(Checkpoint, APreviousCheckpointAloneIsStillResumed) {
  const Scene scene = two_cell_scene("explicit");
  const fs::path straight = fs::temp_directory_path() / "rbcflow_ckpt_prev_alone_straight";
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_prev_alone";
  fs::remove_all(straight);
  fs::remove_all(dir);
  run_scene(scene, {.out_dir = straight.string(), .threads = 1, .progress = false});
  RunOptions o{.out_dir = dir.string(), .threads = 1, .progress = false, .checkpoint_sim = 10 * scene.dt};
  o.after_step = [](long step) {
    if (step == 35) std::raise(SIGTERM);
  };
  EXPECT_THROW(run_scene(scene, o), RunInterrupted);
  fs::remove(dir / "checkpoint.bin");
  EXPECT_TRUE(has_checkpoint(dir.string()));
  EXPECT_FALSE(has_checkpoint(straight.string() + "_none"));
  o.after_step = nullptr;
  o.resume = true;
  run_scene(scene, o);
  EXPECT_EQ(read_all(dir / "series.csv"), read_all(straight / "series.csv"));
}

// Threads not given: one under GNU parallel or a Slurm array, a Slurm task's CPUs, else OpenMP's.
TEST(Threads, TheDefaultIsOneUnderAJobPoolAndTheTasksCpusUnderSlurm) {
  for (const char* v : {"PARALLEL_SEQ", "SLURM_ARRAY_TASK_ID", "SLURM_CPUS_PER_TASK"}) unsetenv(v);
  EXPECT_EQ(default_threads(), omp_get_max_threads());
  setenv("PARALLEL_SEQ", "3", 1);
  EXPECT_EQ(default_threads(), 1);
  unsetenv("PARALLEL_SEQ");
  setenv("SLURM_ARRAY_TASK_ID", "7", 1);
  EXPECT_EQ(default_threads(), 1);
  setenv("SLURM_CPUS_PER_TASK", "3", 1);
  EXPECT_EQ(default_threads(), 3);
  setenv("SLURM_CPUS_PER_TASK", "none", 1);
  EXPECT_EQ(default_threads(), 1);
  unsetenv("SLURM_ARRAY_TASK_ID");
  unsetenv("SLURM_CPUS_PER_TASK");
}

TEST(Checkpoint, ACheckpointOfAnotherSceneOrVersionOrNoCheckpointIsRefused) {
  Scene scene = two_cell_scene("explicit");
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_other_scene";
  fs::remove_all(dir);
  RunOptions o{.out_dir = dir.string(), .threads = 1, .progress = false};
  o.resume = true;
  EXPECT_NE(error_of([&] { run_scene(scene, o); }).find("no checkpoint to resume from"), std::string::npos);
  o.resume = false;
  o.after_step = [](long step) {
    if (step == 5) std::raise(SIGTERM);
  };
  EXPECT_THROW(run_scene(scene, o), RunInterrupted);
  o.after_step = nullptr;
  o.resume = true;
  scene.dt *= 0.5;
  const std::string m = error_of([&] { run_scene(scene, o); });
  EXPECT_NE(m.find("written for another scene"), std::string::npos) << m;
  EXPECT_NE(m.find("dt = "), std::string::npos) << m;
  // The scene stored in the checkpoint reads back as the scene that wrote it.
  EXPECT_EQ(scene_to_toml(checkpoint_scene(dir.string())), scene_to_toml(two_cell_scene("explicit")));
  // A checkpoint of other code (its code record changed, checksum made valid again).
  scene.dt *= 2.0;
  {
    std::string bytes = read_all(dir / "checkpoint.bin");
    const std::string version = code_id();
    const auto k = bytes.find(version);
    ASSERT_NE(k, std::string::npos);
    bytes.replace(k, version.size(), std::string(version.size(), '9'));
    const std::size_t body = bytes.size() - sizeof(std::uint64_t);
    const std::uint64_t sum = fnv1a64(reinterpret_cast<const unsigned char*>(bytes.data()), body);
    bytes.replace(body, sizeof sum, std::string(reinterpret_cast<const char*>(&sum), sizeof sum));
    std::ofstream(dir / "checkpoint.bin", std::ios::binary | std::ios::trunc) << bytes;
  }
  const std::string v = error_of([&] { run_scene(scene, o); });
  EXPECT_NE(v.find("written by code " + std::string(std::string(code_id()).size(), '9') + ", this is code " + code_id()), std::string::npos) << v;
  EXPECT_THROW(checkpoint_scene(dir.string()), CheckpointError);  // rbcflow resume: refused too
  // ... unless asked (rbcflow resume --any-code), which says so.
  o.any_code = true;
  EXPECT_EQ(scene_to_toml(checkpoint_scene(dir.string(), true)), scene_to_toml(scene));
  testing::internal::CaptureStderr();
  run_scene(scene, o);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("--any-code"), std::string::npos) << said;
}

TEST(Checkpoint, AnUnstableRunStopsNamingTheCauseAndKeepsItsLastGoodCheckpoint) {
  // The explicit coupling at 1e-6 s on a 0.5 um mesh: ten times its stability limit (1.6e-7 s,
  // README), so the membrane blows up within a few tens of steps.
  Scene scene = two_cell_scene("explicit");
  scene.dt = 1e-6;
  scene.end = 400 * scene.dt;
  scene.output_every = scene.dt;
  scene.snapshots = {};
  const fs::path dir = fs::temp_directory_path() / "rbcflow_ckpt_unstable";
  fs::remove_all(dir);
  const std::string m = error_of(
      [&] { run_scene(scene, {.out_dir = dir.string(), .threads = 1, .progress = false, .checkpoint_sim = 2 * scene.dt}); });
  ASSERT_FALSE(m.empty()) << "the run should have gone unstable";
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_NE(m.find(" at t = "), std::string::npos) << m;
  EXPECT_NE(m.find("last good state"), std::string::npos) << m;
  // The checkpoint is readable and older than the failure; series.csv is a complete table.
  ASSERT_TRUE(fs::exists(dir / "checkpoint.bin"));
  EXPECT_NO_THROW(CheckpointReader r((dir / "checkpoint.bin").string()));
  std::ifstream csv(dir / "series.csv");
  std::string header, line;
  while (std::getline(csv, header) && header.rfind('#', 0) == 0) {}  // (the units line)
  const auto columns = std::count(header.begin(), header.end(), ',');
  int rows = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), columns) << line;
    ++rows;
  }
  EXPECT_GE(rows, 2);
}

// The progress line of long runs: durations as the line prints them, and the last line of a run
// gives its wall time and one rate (the last minute's rate only appears part way through a run
// longer than a minute and a bit).
TEST(ProgressLine, DurationsAndTheFinalLine) {
  EXPECT_EQ(format_duration(4.24), "4.2s");
  EXPECT_EQ(format_duration(192), "3m12s");
  EXPECT_EQ(format_duration(3720), "1h02m");
  EXPECT_EQ(format_duration(INFINITY), "?");
  testing::internal::CaptureStderr();
  {
    ProgressMeter p("case", 200, 2e-3, true);
    p.update(100, 1e-3);  // too soon after the start for a line
    p.finish(200, 2e-3);
  }
  const std::string line = testing::internal::GetCapturedStderr();
  EXPECT_NE(line.find("case: t = 0.002 / 0.002 s (100.0 %), step 200/200, "), std::string::npos) << line;
  EXPECT_NE(line.find(" steps/s, wall "), std::string::npos) << line;
  EXPECT_EQ(line.find("last"), std::string::npos) << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;
}

}  // namespace
}  // namespace rbc
