// The scene runner: bad input gets one clear line naming the key and what is allowed; a good
// scene writes summary.json and series.csv as run_scene.hpp names them.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "io/provenance.hpp"
#include "scene/run_scene.hpp"

namespace rbc {
namespace {

const std::string kGood = R"(
[fluid]
density = 1000.0
viscosity = 1.2e-3
[channel]
length = 4e-6
height = 2e-6
mesh_size = 0.25e-6
reynolds = 0.1
[time]
dt = 1e-7
end = 2e-6
[output]
every = 5e-7
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto k = s.find(from);
  EXPECT_NE(k, std::string::npos) << from;
  return s.replace(k, from.size(), to);
}

// The message of the SceneError that parsing `text` throws ("" if none).
std::string scene_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    parse_scene(text, "scene.toml", overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& message, std::initializer_list<const char*> fragments) {
  ASSERT_FALSE(message.empty()) << "expected a SceneError";
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  EXPECT_EQ(message.rfind("scene.toml", 0), 0u) << "names the file: " << message;
  for (const char* f : fragments) EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' in: " << message;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream f(path);
  std::stringstream b;
  b << f.rdbuf();
  return b.str();
}

TEST(SceneKeys, TheReferencePageListsExactlyTheParsersKeys) {
  // paper/scene_keys.md has one table row per key, "| `table.key` | unit | default | allowed |".
  // Its keys and the parser's (scene_keys()) must be the same set: a key added to the parser
  // without its line, or a line for a key the parser refuses, fails here.
  const std::string page = read_text(std::filesystem::path(RBCFLOW_SOURCE_DIR) / "paper/scene_keys.md");
  std::set<std::string> documented;
  std::istringstream in(page);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("| `", 0) == 0) documented.insert(line.substr(3, line.find('`', 3) - 3));
  const std::vector<std::string> keys = scene_keys();
  const std::set<std::string> parsed(keys.begin(), keys.end());
  for (const std::string& k : parsed) EXPECT_TRUE(documented.count(k)) << k << " is read by the parser but not in paper/scene_keys.md";
  for (const std::string& k : documented) EXPECT_TRUE(parsed.count(k)) << k << " is in paper/scene_keys.md but the parser refuses it";
  EXPECT_GT(parsed.size(), 40u);
}

TEST(SceneKeys, TheReadmesSceneParsesAndRuns) {
  // The scene shown in README.md, as a user would copy it: valid TOML, a valid scene, and a run
  // (shortened to 0.1 ms) that ends with its cell inside the channel.
  const std::string readme = read_text(std::filesystem::path(RBCFLOW_SOURCE_DIR) / "README.md");
  const std::size_t a = readme.find("```toml\n");
  ASSERT_NE(a, std::string::npos) << "README.md has no ```toml block";
  const std::size_t b = readme.find("```", a + 8);
  const std::string text = readme.substr(a + 8, b - a - 8);
  const Scene scene = parse_scene(text, "README.md (its scene)", {"time.end=1e-4"});
  ASSERT_EQ(scene.cells.size(), 1u);
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_readme_scene";
  std::filesystem::remove_all(out);
  const RunSummary s = run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  EXPECT_EQ(s.steps, 50);
  ASSERT_EQ(s.cells.size(), 1u);
  EXPECT_GT(s.cells[0].centroid.y(), 0.0);
  EXPECT_LT(s.cells[0].centroid.y(), scene.height);
}

TEST(SceneInput, GoodSceneParsesWithUnitsAsWritten) {
  const Scene s = parse_scene(kGood, "scene.toml");
  EXPECT_DOUBLE_EQ(s.length, 4e-6);
  EXPECT_DOUBLE_EQ(*s.reynolds0, 0.1);
  EXPECT_DOUBLE_EQ(s.driving_force(), body_force_from_reynolds(0.1, s.fluid, 2e-6));
}

TEST(SceneInput, UnknownKeyIsRejectedWithTheNearestValidKey) {
  expect_error(scene_error(replace(kGood, "mesh_size", "mesh_sise")), {"[channel] mesh_sise", "unknown key", "did you mean 'mesh_size'"});
  expect_error(scene_error(kGood + "[outptu]\nevery = 1e-6\n"), {"unknown table", "did you mean 'output'"});
}

TEST(SceneInput, MissingRequiredKeysAreNamed) {
  expect_error(scene_error(replace(kGood, "height = 2e-6\n", "")), {"[channel] height", "missing required key", "m)"});
  expect_error(scene_error(replace(kGood, "reynolds = 0.1\n", "")), {"reynolds", "body_force"});
  expect_error(scene_error(""), {"missing required key"});
}

TEST(SceneInput, ValuesOutOfRangeOrOfTheWrongTypeAreRejected) {
  expect_error(scene_error(replace(kGood, "viscosity = 1.2e-3", "viscosity = -1.0")), {"[fluid] viscosity", "out of range", "Pa s"});
  expect_error(scene_error(replace(kGood, "length = 4e-6", "length = \"long\"")), {"[channel] length", "must be a number", "a string"});
  expect_error(scene_error(replace(kGood, "length = 4e-6", "length = nan")), {"[channel] length", "out of range"});
  expect_error(scene_error(replace(kGood, "reynolds = 0.1", "reynolds = 0.1\nbody_force = 3.0")), {"not both"});
  expect_error(scene_error(replace(kGood, "end = 2e-6", "end = 1e-8")), {"[time] end", "at least one time step"});
  // A step count beyond kMaxSteps is a unit slip (before: lround overflowed into a run of no steps).
  expect_error(scene_error(kGood, {"time.dt=1e-300"}), {"[time]", "end / dt = 2e+294 steps", "units of [time] dt and end"});
  expect_error(scene_error(replace(kGood, "[output]", "[solver]\ncg_max_iterations = 0\n[output]")), {"[solver] cg_max_iterations", "out of range"});
  expect_error(scene_error(replace(kGood, "[output]", "[output]\nvtk = 1")), {"[output] vtk", "true or false"});
  expect_error(scene_error(replace(kGood, "[output]", "[output]\nvtk = true\nvtk_every = 1e-7")),
               {"[output] vtk_every", "1e-07 s", "at least [output] every = 5e-07 s"});
  expect_error(scene_error(kGood + "[solver]\npressure_preconditioner = \"shur\"\n"), {"did you mean 'schur'"});
  expect_error(scene_error(replace(kGood, "[output]", "[output]\nframes = -1")), {"[output] frames", "out of range"});
  expect_error(scene_error(replace(kGood, "[output]", "[output]\nframes = 0.5")), {"[output] frames", "integer"});
}

TEST(SceneInput, CouplingIsNamedAndTheSemiImplicitTableIsBounded) {
  expect_error(scene_error(kGood, {"time.coupling=implicit"}), {"[time] coupling", "explicit", "semi-implicit"});
  const std::string cell = "[[cell]]\ncenter = [2e-6, 1e-6]\nswelling_ratio = 0.55\n[membrane]\nradius = 0.5e-6\n";
  EXPECT_EQ(scene_error(kGood + cell, {"time.coupling=semi-implicit"}), "");
  // How the coupled GMRES solves is the library's (CouplingOptions), not the scene's: the keys that
  // once chose it are refused with a message that says so.
  for (const char* key : {"coupling_start", "coupling_blocks", "coupling_solves"})
    expect_error(scene_error(kGood + cell + "[solver]\n" + key + " = \"constant\"\n", {"time.coupling=semi-implicit"}),
                 {key, "no longer a scene key", "CouplingOptions"});
  // 25 um x 0.5 mm at h = 0.25 um: 100 x 2000 cells, a 24 GiB table.
  expect_error(scene_error(kGood + cell, {"time.coupling=semi-implicit", "channel.length=25e-6", "channel.height=0.5e-3"}),
               {"[time] coupling", "GiB", "coarser"});
}

TEST(SceneInput, MeshSizeThatDoesNotDivideTheChannelNamesTheSide) {
  expect_error(scene_error(replace(kGood, "height = 2e-6", "height = 2.1e-6")), {"[channel] mesh_size", "height"});
  expect_error(scene_error(replace(kGood, "length = 4e-6", "length = 4.3e-6")), {"[channel] mesh_size", "length"});
}

TEST(SceneInput, TimeStepAboveTheAdvectiveBoundIsRejected) {
  // Re0 = 50 in this tiny channel: U_max = 1.5 U0 = 45 m/s, bound 0.5 h / U_max = 2.8e-9 s.
  expect_error(scene_error(replace(kGood, "reynolds = 0.1", "reynolds = 50")), {"[time] dt", "advective bound"});
  // More wave-like substeps raise the bound.
  EXPECT_EQ(scene_error(replace(kGood, "reynolds = 0.1", "reynolds = 50"), {"time.advection_substeps=40"}), "");
}

TEST(SceneInput, DisksAreReadAndAWrongOneIsRefusedClearly) {
  EXPECT_EQ(scene_error(kGood + "[[disk]]\ncenter = [2e-6, 1e-6]\nradius = 0.5e-6\n"), "");
  expect_error(scene_error(kGood + "[[disk]]\ncenter = [1e-6, 0.6e-6]\nradius = 0.5e-6\n"), {"[[disk]] 0 center", "one mesh cell"});
}

// A channel wide enough for cells (the study's narrow channel on a coarse mesh).
std::string cell_channel() {
  return replace(replace(replace(kGood, "length = 4e-6", "length = 20e-6"), "height = 2e-6", "height = 10e-6"),
                 "mesh_size = 0.25e-6", "mesh_size = 0.5e-6");
}

TEST(SceneInput, CellsAreReadAndBadCellsAreNamed) {
  const Scene s = parse_scene(cell_channel() + "[[cell]]\ncenter = [5e-6, 3e-6]\nswelling_ratio = 0.55\n", "scene.toml");
  ASSERT_EQ(s.cells.size(), 1u);
  EXPECT_DOUBLE_EQ(s.cells[0].swelling_ratio, 0.55);
  expect_error(scene_error(cell_channel() + "[[cell]]\ncentre = [5e-6, 3e-6]\nswelling_ratio = 0.55\n"),
               {"[[cell]] 0 centre", "did you mean 'center'"});
  expect_error(scene_error(cell_channel() + "[[cell]]\ncenter = [5e-6, 3e-6]\n"), {"[[cell]] 0 swelling_ratio", "missing"});
  expect_error(scene_error(cell_channel() + "[[cell]]\ncenter = [5e-6, 3e-6]\nswelling_ratio = 1.2\n"), {"swelling_ratio", "out of range"});
  expect_error(scene_error(cell_channel() + "[[cell]]\ncenter = [5e-6, 0.5e-6]\nswelling_ratio = 0.55\n"),
               {"[[cell]] 0", "outside the channel"});
  expect_error(scene_error(cell_channel() + "[[cell]]\ncenter = [5e-6, 3e-6]\nswelling_ratio = 0.55\n"
                                          "[[cell]]\ncenter = [7e-6, 3.5e-6]\nswelling_ratio = 0.7\n"),
               {"[[cell]] 0 and 1", "overlap"});
  // Overlap across the periodic boundary x1 = L = 20 um.
  expect_error(scene_error(cell_channel() + "[[cell]]\ncenter = [1e-6, 5e-6]\nswelling_ratio = 0.55\n"
                                          "[[cell]]\ncenter = [19.5e-6, 5e-6]\nswelling_ratio = 0.55\n"),
               {"overlap"});
  expect_error(scene_error(cell_channel() + "[membrane]\nunits = \"mks\"\n"), {"[membrane] units", "si"});
}

TEST(SceneInput, InvalidTomlOrBinaryInputIsRejectedWithoutCrashing) {
  expect_error(scene_error("[channel\nlength = 1"), {"not valid TOML"});
  expect_error(scene_error(std::string("\x7f" "ELF\0\x01\x02", 7)), {"binary"});
  expect_error(scene_error("length = 1e-6\n"), {"unknown table", "'length'"});
}

TEST(SceneInput, SetOverridesAKeyAndBadOverridesAreNamed) {
  const Scene s = parse_scene(kGood, "scene.toml", {"time.dt=5e-8", "solver.pressure_preconditioner=laplacian"});
  EXPECT_DOUBLE_EQ(s.dt, 5e-8);
  EXPECT_EQ(s.pressure_preconditioner, "laplacian");
  expect_error(scene_error(kGood, {"dt=1e-8"}), {"expected table.key=value"});
  expect_error(scene_error(kGood, {"time.dtt=1e-8"}), {"did you mean 'dt'"});
}

TEST(SceneRunner, WritesSummaryJsonAndSeriesCsvWithTheNamedQuantities) {
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_outputs";
  std::filesystem::remove_all(out);
  const Scene scene = parse_scene(kGood, "scene.toml");
  const RunSummary s = run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  EXPECT_EQ(s.steps, 20);
  std::ifstream js(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  for (const char* key : {"steps", "t_end", "wall_seconds", "mean_velocity", "reynolds", "hematocrit", "cells", "disks"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["steps"].get<long>(), 20);
  EXPECT_NEAR(j["t_end"].get<double>(), 2e-6, 1e-15);
  std::ifstream csv(out / "series.csv");
  std::string units, header, line;
  std::getline(csv, units);
  std::getline(csv, header);
  EXPECT_EQ(units.rfind("# units: s,m/s,1,%", 0), 0u) << units;  // SI, one unit per column
  EXPECT_EQ(std::count(units.begin(), units.end(), ','), std::count(header.begin(), header.end(), ','));
  EXPECT_EQ(header.rfind("t,mean_velocity,reynolds,hematocrit", 0), 0u) << header;
  int samples = 0;
  while (std::getline(csv, line)) ++samples;
  EXPECT_EQ(samples, 5);  // t = 0 and every 5e-7 s to 2e-6 s
}

// The movie's frames (frames.dat): its outlines per frame, by kind, and the cells' x1 range.
struct Frames {
  std::vector<double> times;                          // s
  std::vector<std::map<int, int>> outlines;           // per frame: outlines of each kind
  std::vector<std::pair<double, double>> cell_x;      // per frame: the cells' smallest and largest x1 (m)
  std::string header;
};

Frames read_frames(const std::filesystem::path& path) {
  Frames fr;
  std::ifstream f(path);
  std::getline(f, fr.header);
  std::string line;
  int rows = 0, kind = -1;
  while (std::getline(f, line)) {
    if (line.rfind("# t = ", 0) == 0) {
      fr.times.push_back(std::stod(line.substr(6)));
      fr.outlines.emplace_back();
      fr.cell_x.emplace_back(1e9, -1e9);
    } else if (line.empty()) {
      if (rows > 0) ++fr.outlines.back()[kind];
      rows = 0;
    } else if (line[0] != '#') {
      std::istringstream row(line);
      double x = 0, y = 0;
      int id = -1;
      row >> x >> y >> kind >> id;
      EXPECT_EQ(id, 0) << line;
      if (kind == 0) fr.cell_x.back() = {std::min(fr.cell_x.back().first, x), std::max(fr.cell_x.back().second, x)};
      ++rows;
    }
  }
  return fr;
}

// frames + 1 frames at k end/frames, each with every cell's closed outline in m (kind 0), a
// disk's outline and its radius (kind 1), an obstacle's rectangle (kind 2); a cell across
// x1 = L = 20 um is drawn on both sides.
TEST(SceneRunner, MovieFramesHoldEveryBodyAtTheirTimes) {
  const auto dir = std::filesystem::temp_directory_path() / "rbcflow_runner_frames";
  std::filesystem::remove_all(dir);
  const std::string frames4 = replace(cell_channel(), "[output]", "[output]\nframes = 4");
  const Scene cell_and_disk = parse_scene(frames4 + "[[cell]]\ncenter = [19e-6, 5e-6]\nswelling_ratio = 0.7\n"
                                                    "[[disk]]\ncenter = [10e-6, 5e-6]\nradius = 1e-6\n", "scene.toml");
  run_scene(cell_and_disk, {.out_dir = (dir / "cell").string(), .threads = 1, .progress = false});
  const Frames a = read_frames(dir / "cell" / "frames.dat");
  EXPECT_NE(a.header.find("(m): 2e-05 1e-05"), std::string::npos) << a.header;
  ASSERT_EQ(a.times.size(), 5u);
  for (int k = 0; k <= 4; ++k) {
    EXPECT_NEAR(a.times[k], k * cell_and_disk.end / 4, 0.5 * cell_and_disk.dt);
    EXPECT_EQ(a.outlines[k].at(0), 2) << "the cell across x1 = L, on both sides";
    EXPECT_EQ(a.outlines[k].at(1), 2) << "the disk's outline and its radius";
  }
  EXPECT_LT(a.cell_x.front().first, 0.0);   // the copy one period back reaches below x1 = 0 ...
  EXPECT_GT(a.cell_x.front().second, 20e-6);  // ... and the cell itself past L
  const Scene obstacle = parse_scene(frames4 + "[[obstacle]]\nx = [6e-6, 8e-6]\ny = [0.0, 1e-6]\nwall = \"bottom\"\n", "scene.toml");
  run_scene(obstacle, {.out_dir = (dir / "obstacle").string(), .threads = 1, .progress = false});
  const Frames b = read_frames(dir / "obstacle" / "frames.dat");
  ASSERT_EQ(b.times.size(), 5u);
  for (const auto& o : b.outlines) EXPECT_EQ(o, (std::map<int, int>{{2, 1}}));
}

// A finished run is read back (--reuse) only for the scene that made it: another time step, form
// of the pressure splitting or time scheme runs again; a summary older than the "projection" and
// "scheme" keys counts as the study's form and scheme.
TEST(SceneRunner, AFinishedRunIsReusedOnlyForItsOwnScheme) {
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_reuse";
  std::filesystem::remove_all(out);
  const Scene scene = parse_scene(kGood, "scene.toml");
  ASSERT_EQ(scene.projection, "study");
  run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  EXPECT_TRUE(read_finished_run(out.string(), scene).has_value());
  EXPECT_FALSE(read_finished_run(out.string(), parse_scene(kGood, "scene.toml", {"time.projection=\"incremental\""})).has_value());
  EXPECT_FALSE(read_finished_run(out.string(), parse_scene(kGood, "scene.toml", {"time.dt=5e-8"})).has_value());
  const Scene extrapolated = parse_scene(kGood, "scene.toml", {"time.scheme=\"lie-extrapolated\""});
  ASSERT_EQ(extrapolated.scheme, "lie-extrapolated");
  EXPECT_FALSE(read_finished_run(out.string(), extrapolated).has_value());
  nlohmann::json j = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(j["projection"], "study");
  EXPECT_EQ(j["scheme"], "lie");
  j.erase("projection");
  j.erase("scheme");
  std::ofstream(out / "summary.json") << j.dump();
  EXPECT_TRUE(read_finished_run(out.string(), scene).has_value());
  EXPECT_FALSE(read_finished_run(out.string(), parse_scene(kGood, "scene.toml", {"time.projection=\"incremental\""})).has_value());
  EXPECT_FALSE(read_finished_run(out.string(), extrapolated).has_value());
  // The extrapolated scheme's pressure choice and a disk's boundary points are told apart too (a
  // summary without them: their defaults).
  const auto other = std::filesystem::temp_directory_path() / "rbcflow_runner_reuse_keys";
  std::filesystem::remove_all(other);
  const Scene half_pressure = parse_scene(kGood, "scene.toml", {"time.scheme=\"lie-extrapolated\"", "time.extrapolate_pressure=false"});
  run_scene(half_pressure, {.out_dir = other.string(), .threads = 1, .progress = false});
  EXPECT_TRUE(read_finished_run(other.string(), half_pressure).has_value());
  EXPECT_FALSE(read_finished_run(other.string(), extrapolated).has_value());
  const std::string disk = kGood + "[[disk]]\ncenter = [2e-6, 1e-6]\nradius = 0.6e-6\n";
  const Scene one_h = parse_scene(disk, "scene.toml"), two_h = parse_scene(disk, "scene.toml", {"solver.disk_boundary_spacing=2"});
  std::filesystem::remove_all(other);
  run_scene(two_h, {.out_dir = other.string(), .threads = 1, .progress = false});
  EXPECT_TRUE(read_finished_run(other.string(), two_h).has_value());
  EXPECT_FALSE(read_finished_run(other.string(), one_h).has_value());
  // The resolved scene names the scheme only when it is not the study's (so that the study's
  // resolved scenes read as before the key), and reads back to the same scene.
  EXPECT_EQ(scene_to_toml(scene).find("scheme"), std::string::npos);
  EXPECT_EQ(parse_scene(scene_to_toml(extrapolated), "resolved.toml").scheme, "lie-extrapolated");
}

TEST(SceneRunner, AResultsFolderSaysWhatMadeItAndRepeatsFromItsSceneFile) {
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_provenance";
  std::filesystem::remove_all(out);
  const char* argv[] = {"rbcflow", "run", "scene.toml", "--set", "time.end=2e-6"};
  set_command_line(5, argv);
  const Scene scene = parse_scene(kGood, "scene.toml");
  run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  // The resolved scene beside the results: it parses to the scene that ran.
  std::ifstream f(out / "scene.toml");
  ASSERT_TRUE(f.good());
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Scene again = parse_scene(text, (out / "scene.toml").string());
  again.source = scene.source;  // (the file's name is its source)
  EXPECT_EQ(scene_to_toml(again), scene_to_toml(scene));
  EXPECT_NE(text.find(std::string("code ") + code_id()), std::string::npos);
  // The summary names the code, the commit, the command and when it ran.
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(j.at("code"), code_id());
  EXPECT_EQ(j.at("commit"), commit_id());
  EXPECT_EQ(j.at("command"), "rbcflow run scene.toml --set time.end=2e-6");
  EXPECT_EQ(j.at("started").get<std::string>().size(), 20u);  // 2026-11-29T09:30:00Z
  EXPECT_GE(j.at("ended").get<std::string>(), j.at("started").get<std::string>());
  // A finished run of other code is not reused (it runs again), unless read as kept evidence.
  EXPECT_TRUE(read_finished_run(out.string(), scene).has_value());
  nlohmann::json other = j;
  other["code"] = "0123456789ab";
  std::ofstream(out / "summary.json") << other.dump();
  EXPECT_FALSE(read_finished_run(out.string(), scene).has_value());
  EXPECT_TRUE(read_finished_run(out.string(), scene, true).has_value());
}

TEST(SceneRunner, AFolderHoldsOneRunAtATime) {
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_one_run";
  std::filesystem::remove_all(out);
  const Scene scene = parse_scene(kGood, "scene.toml");
  run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  // Another run's files in the folder: refused where asked (rbcflow run without --overwrite)...
  const std::string refused = [&] {
    try {
      run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false, .refuse_other_run = true});
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(refused.find("holds another run"), std::string::npos) << refused;
  EXPECT_NE(refused.find("--overwrite"), std::string::npos) << refused;
  // ... else cleared first: an old run's checkpoint and fields do not stay beside the new run.
  std::ofstream(out / "checkpoint.bin.prev") << "an old run's";
  std::ofstream(out / "field_3.dat") << "an old run's";
  run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  EXPECT_FALSE(std::filesystem::exists(out / "checkpoint.bin.prev"));
  EXPECT_FALSE(std::filesystem::exists(out / "field_3.dat"));
  EXPECT_TRUE(std::filesystem::exists(out / "summary.json"));
  // A second process on the folder (its lock held here): stops at once, naming the folder.
  const int fd = ::open((out / ".lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  try {
    run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
    ADD_FAILURE() << "two runs in one folder";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("another rbcflow process is running in this folder"), std::string::npos) << e.what();
  }
  ::close(fd);
  EXPECT_NO_THROW(run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false}));  // the lock released
}

TEST(SceneRunner, AnOutputThatCannotBeWrittenStopsTheRunNamingTheFile) {
  // An output on the device that is always full (the disk-full case; scene.toml, the one output a
  // fresh run does not clear first): before, failed writes went unnoticed (series.csv's rows lost,
  // the run "successful"); now the run stops naming the file.
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_full";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  std::filesystem::create_symlink("/dev/full", out / "scene.toml");
  const Scene scene = parse_scene(kGood, "scene.toml");
  try {
    run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
    ADD_FAILURE() << "the run went on without its series";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.toml: cannot write"), std::string::npos) << e.what();
  }
  std::filesystem::remove(out / "scene.toml");  // (the link, not the device)
}

// Where the semi-implicit coupling iterates (several cells, or one with obstacles), how GMRES
// solves (CouplingOptions) and its tolerance are part of the run too. The summary is written by
// hand here (a run of two cells would take seconds for a check of the reading).
TEST(SceneRunner, ACrowdsRunIsReusedOnlyForTheSameCouplingOptionsAndTolerance) {
  const auto out = std::filesystem::temp_directory_path() / "rbcflow_runner_reuse_start";
  std::filesystem::remove_all(out);
  Scene scene = parse_scene(kGood, "scene.toml");
  run_scene(scene, {.out_dir = out.string(), .threads = 1, .progress = false});
  scene.coupling = "semi-implicit";
  scene.cells = {CellSpec{{1e-6, 1e-6}, 0.7, 0.0}, CellSpec{{3e-6, 1e-6}, 0.7, 0.0}};
  nlohmann::json j = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  j["coupling"] = "semi-implicit";
  const auto write = [&] { std::ofstream(out / "summary.json") << j.dump(); };
  write();  // no options recorded: a summary of a version whose solve could differ
  ASSERT_EQ(scene.coupling_tolerance, 1e-4);
  EXPECT_FALSE(read_finished_run(out.string(), scene).has_value());
  j["coupling_options"] = describe(CouplingOptions{});
  j["coupling_tolerance"] = 1e-4;
  write();
  EXPECT_TRUE(read_finished_run(out.string(), scene).has_value());
  Scene tighter = scene;
  tighter.coupling_tolerance = 1e-5;
  EXPECT_FALSE(read_finished_run(out.string(), tighter).has_value());
  CouplingOptions linear;
  linear.start = CouplingOptions::Start::kLinear;
  j["coupling_options"] = describe(linear);
  write();
  EXPECT_FALSE(read_finished_run(out.string(), scene).has_value());
  Scene one = scene;  // one cell: its block is its whole system, GMRES does not run
  one.cells.pop_back();
  EXPECT_TRUE(read_finished_run(out.string(), one).has_value());
  one.obstacles = {Obstacle{{1e-6, 2e-6}, {0.0, 0.5e-6}, "bottom"}};  // ... unless an obstacle makes it iterate
  one.projection = "study";
  EXPECT_FALSE(read_finished_run(out.string(), one).has_value());
  j["coupling_options"] = describe(CouplingOptions{});
  write();
  EXPECT_TRUE(read_finished_run(out.string(), one).has_value());
}

TEST(SceneRunner, UnwritableOutputFolderIsASceneError) {
  const Scene scene = parse_scene(kGood, "scene.toml");
  EXPECT_THROW(run_scene(scene, {.out_dir = "/proc/rbcflow-cannot-write-here", .threads = 1, .progress = false}), SceneError);
}

// The executable: exit codes and one-line messages for bad command lines.
int run_cli(const std::string& args, std::string& err) {
  const auto errfile = std::filesystem::temp_directory_path() / "rbcflow_cli_err.txt";
  const int status = std::system((std::string(RBCFLOW_BIN_DIR) + "/rbcflow " + args + " >/dev/null 2>" + errfile.string()).c_str());
  std::ifstream f(errfile);
  std::stringstream ss;
  ss << f.rdbuf();
  err = ss.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SceneRunnerCli, BadCommandLinesExitNonZeroWithAMessage) {
  std::string err;
  EXPECT_NE(run_cli("run /nonexistent/scene.toml", err), 0);
  EXPECT_NE(err.find("cannot open the scene file"), std::string::npos) << err;
  EXPECT_NE(run_cli("run --frobnicate 3", err), 0);
  EXPECT_FALSE(err.empty());
  EXPECT_NE(run_cli("", err), 0);
}

}  // namespace
}  // namespace rbc

namespace rbc {
namespace {

TEST(SceneFiles, EveryShippedSceneIsValid) {
  // The teaching scenes of paper/method and the experiments' scene files must never rot.
  int n = 0;
  for (const char* dir : {"/paper/method/scenes", "/experiments/channel_flow", "/experiments/constriction", "/experiments/single_cell_migration",
                          "/experiments/four_cells_vs_disks", "/experiments/cell_free_layer"})
    for (const auto& e : std::filesystem::directory_iterator(std::string(RBCFLOW_SOURCE_DIR) + dir))
      if (e.path().extension() == ".toml") {
        EXPECT_NO_THROW(load_scene_file(e.path().string())) << e.path();
        ++n;
      }
  EXPECT_GE(n, 14);
}

}  // namespace
}  // namespace rbc
