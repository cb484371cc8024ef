// The literate reference step (paper/method/reference_step.cpp) takes the library's step: the same
// fractional steps of the study's Lie scheme (Section 2.4) in the same order and forms, so from the
// same start Simulation::step and reference_step reach the same state to round-off.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "reference_step.hpp"  // paper/method (CMakeLists.txt, its reference step block)
#include "scene/simulation.hpp"

namespace rbc {
namespace {

// Round-off: 1e-12, about 4500 ε. A wrong term, a missing force or a step out of order moves the state
// by O(Δt) of its size or more. The two take the same operations in the same order (on one thread:
// bit for bit), and they must: this start from rest grows an ulp (one term of the incremental form
// fused into a multiply-add ended 1.3e-12 of the velocity apart after 100 steps).
constexpr double kRoundOff = 1e-12;

// Largest |a − b| relative to the largest |a|, over both components of a field or both
// coordinates of every node.
double relative_difference(const std::vector<const std::vector<double>*>& a, const std::vector<const std::vector<double>*>& b) {
  double diff = 0, size = 0;
  for (std::size_t c = 0; c < a.size(); ++c)
    for (std::size_t k = 0; k < a[c]->size(); ++k) {
      diff = std::max(diff, std::abs((*a[c])[k] - (*b[c])[k]));
      size = std::max(size, std::abs((*a[c])[k]));
    }
  return size > 0 ? diff / size : diff;
}

struct Comparison {
  double velocity = 0;      // max |Δu| / max |u|
  double pressure = 0;      // max |Δp| / max |p|
  double nodes = 0;         // max |Δr| / max |r| (positions, m)
  double displacement = 0;  // max |Δr| / max |r − r⁰| (what the steps moved the nodes by)
};

// Both steps from the same start, `steps` times, on one thread (the library's sums then run in one
// order), and how far apart they end.
Comparison run_both(const Scene& scene, int steps) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  Simulation sim(scene);
  ReferenceOperators ops(scene);
  ReferenceState ref = reference_start(scene, ops);
  EXPECT_EQ(ref.cells.size(), sim.cells().size());
  for (std::size_t k = 0; k < ref.cells.size(); ++k)  // the same prepared shapes, bit for bit
    EXPECT_EQ(ref.cells[k].nodes, sim.cells()[k].nodes) << "cell " << k;
  EXPECT_EQ(ref.u.u1, sim.flow().velocity().u1);
  const std::vector<Cell> start = ref.cells;
  for (int n = 0; n < steps; ++n) {
    sim.step();
    reference_step(ref, scene, ops);
  }
  omp_set_num_threads(threads_before);
  EXPECT_EQ(ref.steps, sim.steps());
  EXPECT_DOUBLE_EQ(ref.t, sim.time());

  Comparison c;
  const VelocityField& u = sim.flow().velocity();
  c.velocity = relative_difference({&u.u1, &u.u2}, {&ref.u.u1, &ref.u.u2});
  c.pressure = relative_difference({&sim.flow().pressure()}, {&ref.p});
  double diff = 0, size = 0, moved = 0;
  for (std::size_t k = 0; k < ref.cells.size(); ++k)
    for (std::size_t i = 0; i < ref.cells[k].nodes.size(); ++i) {
      const Eigen::Vector2d& r = sim.cells()[k].nodes[i];
      diff = std::max(diff, (r - ref.cells[k].nodes[i]).cwiseAbs().maxCoeff());
      size = std::max(size, r.cwiseAbs().maxCoeff());
      moved = std::max(moved, (r - start[k].nodes[i]).cwiseAbs().maxCoeff());
    }
  c.nodes = diff / size;
  c.displacement = diff / moved;
  std::printf("reference step against Simulation::step, %d steps: velocity %.2g, pressure %.2g, nodes %.2g of the largest "
              "coordinate (%.2g of the largest displacement)\n",
              steps, c.velocity, c.pressure, c.nodes, c.displacement);
  return c;
}

Scene one_cell_coarse(const std::vector<std::string>& overrides = {}) {
  return load_scene_file(std::string(RBCFLOW_SOURCE_DIR) + "/paper/method/scenes/single_cell_coarse.toml", overrides);
}

TEST(ReferenceStep, TakesSimulationsStepToRoundOffOverOneHundredSteps) {
  // The walk-through's scene as it is: one s* = 0.55 cell, the explicit coupling, the study's
  // pressure form.
  const Comparison c = run_both(one_cell_coarse(), 100);
  EXPECT_LE(c.velocity, kRoundOff);
  EXPECT_LE(c.pressure, kRoundOff);
  EXPECT_LE(c.nodes, kRoundOff);
  EXPECT_LE(c.displacement, kRoundOff);
}

TEST(ReferenceStep, TakesSimulationsStepInTheIncrementalPressureFormToo) {
  // The other pressure form (step 4 carries the force of pⁿ, step 1 finds the increment).
  const Comparison c = run_both(one_cell_coarse({"time.projection=incremental"}), 100);
  EXPECT_LE(c.velocity, kRoundOff);
  EXPECT_LE(c.pressure, kRoundOff);
  EXPECT_LE(c.nodes, kRoundOff);
  EXPECT_LE(c.displacement, kRoundOff);
}

TEST(ReferenceStep, RefusesASceneItDoesNotCover) {
  // The semi-implicit coupling adds a correction after step 4 that the reference does not take.
  EXPECT_THROW(ReferenceOperators(one_cell_coarse({"time.coupling=semi-implicit"})), std::invalid_argument);
}

TEST(ReferenceStep, TheWalkThroughsLineLinksSpanTheirFunctions) {
  // paper/method/README.md links each stage to a line range of reference_step.cpp: each range holds
  // the function it names and ends at that function's closing brace.
  const std::string dir = std::string(RBCFLOW_SOURCE_DIR) + "/paper/method/";
  std::ifstream readme_file(dir + "README.md"), source_file(dir + "reference_step.cpp");
  std::stringstream readme;
  readme << readme_file.rdbuf();
  std::vector<std::string> lines;
  for (std::string line; std::getline(source_file, line);) lines.push_back(line);
  const std::regex link(R"(\[`(\w+)`, lines (\d+)–(\d+)\]\(reference_step\.cpp#L(\d+)-L(\d+)\))");
  const std::string text = readme.str();
  int links = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it, ++links) {
    const std::string name = (*it)[1];
    const int first = std::stoi((*it)[2]), last = std::stoi((*it)[3]);
    EXPECT_EQ(first, std::stoi((*it)[4])) << name;
    EXPECT_EQ(last, std::stoi((*it)[5])) << name;
    ASSERT_TRUE(first >= 1 && first <= last && last <= int(lines.size())) << name;
    bool defined = false;
    for (int l = first; l <= last; ++l) defined = defined || lines[l - 1].find(name + "(") != std::string::npos;
    EXPECT_TRUE(defined) << name << " is not within lines " << first << "-" << last;
    EXPECT_EQ(lines[last - 1], "}") << name << ": line " << last << " does not close a function";
  }
  EXPECT_EQ(links, 7);  // the operators, the start, steps (1)-(4) and the step
}

}  // namespace
}  // namespace rbc
