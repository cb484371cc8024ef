#include "stability_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "cell_free_layer/cell_free_layer.hpp"
#include "common/case_runner.hpp"
#include "four_cells_vs_disks/four_cells_vs_disks.hpp"
#include "scene/simulation.hpp"

namespace rbc::stability_map {

Params Params::quick_params() {
  Params p;
  p.quick = true;
  p.out_dir = "results/stability_map_quick";
  p.mesh_sizes = {0.5e-6, 0.25e-6};
  p.kl_scales = {0.1, 1, 10};
  p.kb_scales = {1000};
  p.steps = 200;
  p.ratio = 1.3;
  p.couplings = {"explicit", "semi-implicit"};
  return p;
}

Params Params::report_params() {
  Params p;
  p.mesh_sizes = {0.5e-6, 0.25e-6};
  return p;
}

namespace {

// The narrow channel of the study with one s* = 0.55 cell at (5, 3) µm; coupling: a kind of
// case_runner (its [time] coupling and scheme).
Scene narrow_scene(double h, const std::string& coupling, double kl_scale, double kb_scale) {
  Scene s;
  s.source = "stability_map";
  s.length = 20e-6;
  s.height = 10e-6;
  s.mesh_size = h;
  s.reynolds0 = 0.5556;
  s.coupling = case_runner::coupling_of(coupling);
  s.scheme = case_runner::scheme_of(coupling);
  s.membrane_constants.kl *= kl_scale;
  s.membrane_constants.kb *= kb_scale;
  s.cells.push_back({{5e-6, 3e-6}, 0.55, 0.0});
  return s;
}

double advective_bound_q1(const Scene& s) {
  Scene t = s;
  t.advection_substeps = 1;
  return advective_dt_bound(t.flow_params());
}

// Runs a scene at dt for the trial length; returns "" if stable, else the cause.
std::string trial(Scene s, double dt, int steps, double min_time, double& wall) {
  const double bound1 = advective_bound_q1(s);
  s.dt = dt;
  s.advection_substeps = std::max(1, int(std::ceil(dt / bound1 * (1 + 1e-12))));
  const long n = std::max<long>(steps, long(std::ceil(min_time / dt)));
  s.end = n * dt;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Simulation sim(s);
    for (long k = 0; k < n; ++k) {
      sim.step();
      sim.check_health();
    }
  } catch (const RunFailure& e) {
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string m = e.what();
    return m.substr(0, std::min(m.find(':'), m.find(" at t =")));  // the cause ("CFL", "cell 0 crossed a wall …")
  }
  wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return "";
}

Point bisect(const Params& p, const std::string& coupling, double h, double kl, double kb) {
  Point pt;
  pt.coupling = coupling;
  pt.h = h;
  pt.kl_scale = kl;
  pt.kb_scale = kb;
  const Scene s = narrow_scene(h, coupling, kl, kb);
  pt.cap = p.max_substeps * advective_bound_q1(s);
  double wall = 0;
  // Bracket: the explicit search starts near our measured limit (3e-8 s at h = 0.125 µm) scaled
  // by h and roughly by the stiffness; the semi-implicit one at the cap. Steps of ×3 / ÷3.
  double lo = 0, hi = 0;
  double dt = std::min(pt.cap, 3e-8 * (h / 0.125e-6) / std::pow(std::max(kl, kb / 100), 0.6));
  if (coupling != "explicit") dt = pt.cap;
  for (int guard = 0; guard < 40 && (lo == 0 || hi == 0); ++guard) {
    const std::string cause = trial(s, dt, p.steps, p.min_time, wall);
    ++pt.trials;
    if (cause.empty()) {
      lo = dt;
      if (dt >= pt.cap) break;
      dt = std::min(pt.cap, dt * 3);
    } else {
      hi = dt;
      pt.cause = cause;
      dt /= 3;
    }
  }
  while (lo > 0 && hi > 0 && hi / lo > p.ratio) {
    const double mid = std::sqrt(lo * hi);
    const std::string cause = trial(s, mid, p.steps, p.min_time, wall);
    ++pt.trials;
    if (cause.empty()) lo = mid;
    else { hi = mid; pt.cause = cause; }
  }
  pt.stable = lo;
  pt.unstable = hi;
  return pt;
}

Extreme run_extreme(const std::string& name, const std::string& what, Scene s, const Params& p) {
  Extreme e;
  e.name = name;
  e.what = what;
  e.coupling = s.coupling;
  e.dt = s.dt;
  e.end = s.end;
  double wall = 0;
  const long steps = long(std::llround(s.end / s.dt));
  const std::string cause = trial(s, s.dt, int(steps), 0.0, wall);
  e.stable = cause.empty();
  char buf[128];
  std::snprintf(buf, sizeof buf, "ran %ld steps to t = %.3g s", steps, s.end);
  e.outcome = e.stable ? buf : "stopped: " + cause;
  e.wall_seconds = wall;
  if (p.progress) std::printf("  extreme %-22s %-14s dt %.2g s: %s (%.1f s)\n", name.c_str(), s.coupling.c_str(), s.dt, e.outcome.c_str(), wall);
  return e;
}

std::vector<Extreme> extremes(const Params& p) {
  // The extreme cases (stiff membranes, a cell one mesh cell from a wall, the most deflated cell
  // through the 15 µm passage, Hct 34 %, Re0 0.01 and 50), each run with the semi-implicit coupling at the flow's Δt
  // (the advective bound with Q = 2, capped at 1e-6 s) on h = 0.25 µm, for 0.5 ms (0.2 ms quick).
  std::vector<Extreme> out;
  const double h = 0.25e-6, end = p.quick ? 2e-4 : 5e-4;
  auto base = [&](double re0) {
    Scene s = narrow_scene(h, "semi-implicit", 1, 1);
    s.reynolds0 = re0;
    s.advection_substeps = 2;
    s.dt = std::min(1e-6, 0.99 * advective_dt_bound(s.flow_params()));
    s.end = std::ceil(end / s.dt) * s.dt;
    return s;
  };
  for (double re0 : {0.01, 50.0}) {
    Scene s = base(re0);
    char n[32];
    std::snprintf(n, sizeof n, "Re0 = %g", re0);
    out.push_back(run_extreme(n, "one s* = 0.55 cell at (5, 3) um", s, p));
  }
  {
    // The prepared s* = 0.55 shape lying flat: its lowest node one mesh cell above the wall.
    Scene s = base(0.5556);
    const MembraneModel m = s.membrane_model();
    const PreparedShape shape = prepare_shape(m, 0.55);
    const Points r = place_shape(shape, {0, 0}, 0.0);
    double ymin = 1e9;
    for (const auto& q : r) ymin = std::min(ymin, q.y());
    s.cells[0].center = {5e-6, h - ymin};
    out.push_back(run_extreme("one cell from the wall", "lowest node h = 0.25 um above the wall", s, p));
  }
  {
    Scene s = base(0.5556);
    s.cells.clear();
    for (int i = 0; i < 5; ++i) s.cells.push_back({{(2.0 + 4.0 * i) * 1e-6, 5e-6}, 0.55, 1.5707963});
    out.push_back(run_extreme("Hct 34 %", "five s* = 0.55 cells across the flow, 4 um apart (Hct 33.9 %)", s, p));
  }
  {
    Scene s = base(0.5556);
    s.cells[0].swelling_ratio = 0.481;
    out.push_back(run_extreme("s* = 0.481", "the study's most deflated cell (no constriction yet)", s, p));
  }
  {
    // The constriction experiment's cell through its passage: a 40 x 30 um channel at
    // the constriction's Re0 = 1.667 with blocks 7.5 um high on each wall (a 15 um passage, here
    // 10 um long so that the cell crosses it within the case's time), the s* = 0.481 cell on the
    // centreline 4 um upstream of the entry; the flow's Δt as for the others.
    Scene s = base(1.667);
    s.length = 40e-6;
    s.height = 30e-6;
    s.projection = "incremental";
    s.obstacles = {Obstacle{{15e-6, 25e-6}, {0.0, 7.5e-6}, "bottom"}, Obstacle{{15e-6, 25e-6}, {22.5e-6, 30e-6}, "top"}};
    s.cells[0] = {{11e-6, 15e-6}, 0.481, 0.0};
    s.dt = std::min(1e-6, 0.99 * advective_dt_bound(s.flow_params()));
    s.end = std::ceil(end / s.dt) * s.dt;
    out.push_back(run_extreme("s* = 0.481 in 15 um passage", "40 x 30 um, blocks 10 x 7.5 um on both walls, cell 4 um before the entry", s, p));
  }
  {
    Scene s = base(0.5556);
    s.membrane_constants.kb *= 1000;
    s.membrane_constants.kl *= 100;
    out.push_back(run_extreme("k_l x100, k_b x1000", "the stiffest corner of the map", s, p));
  }
  {
    // The four_cells_vs_disks experiment's stiffest case at its own scheme: four s* = 1
    // cells with 1000 k_b each in the wide channel, h = 0.3125 um, semi-implicit, Δt = 6e-6 s, Q = 4
    // (the scene of four_cells_vs_disks.toml, so the map follows the experiment's choices).
    four_cells_vs_disks::Case c;
    c.name = "kb1000";
    c.kb_scale = 1000;
    Scene s = four_cells_vs_disks::case_scene(c, false);
    s.source = "stability_map four_cells_vs_disks kb1000";
    s.end = std::ceil(end / s.dt) * s.dt;
    s.snapshots.clear();
    out.push_back(run_extreme("4 cells 1000 k_b, wide", "four_cells_vs_disks' 1000 k_b case at its dt (6 us), 100 x 50 um, h = 0.3125 um", s, p));
  }
  {
    // Hct 34 % at the cell_free_layer experiment's own scheme: its 100 s* = 0.7
    // cells (seed 1) in the wide channel, h = 0.3125 um, semi-implicit, Δt = 3e-6 s, Q = 4, with
    // the membrane repulsion of its 100-cell cases (cell_free_layer.hpp); from rest.
    cell_free_layer::Case c;
    c.name = "n100";
    c.cells = 100;
    c.repulsion = cell_free_layer::kRepulsionStrength;
    Scene s = cell_free_layer::case_scene(c, false);
    s.source = "stability_map cell_free_layer n100";
    s.end = std::ceil(end / s.dt) * s.dt;
    s.snapshots.clear();
    out.push_back(run_extreme("100 cells Hct 34 %, wide", "cell_free_layer's 100 cells at its dt (3 us, repulsion 2h), 100 x 50 um, h = 0.3125 um", s, p));
  }
  return out;
}

}  // namespace

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    else if (ch == ',' && !quoted) { out.push_back(cur); cur.clear(); }
    else cur += ch;
  }
  out.push_back(cur);
  return out;
}

constexpr const char* kPointHeader = "coupling,h_um,kl_scale,kb_scale,dt_stable_s,dt_unstable_s,dt_cap_s,cause,trials";
constexpr const char* kExtremeHeader = "case,setup,coupling,dt_s,end_s,stable,outcome,wall_seconds";

// A point as a row of stability_map.csv (12 digits: the limits read back must meet the quick
// record's 1e-9 band), and back; false if the row is unreadable.
std::string point_row(const Point& pt) {
  std::ostringstream row;
  row.precision(12);
  row << pt.coupling << "," << pt.h * 1e6 << "," << pt.kl_scale << "," << pt.kb_scale << "," << pt.stable << "," << pt.unstable << ","
      << pt.cap << "," << pt.cause << "," << pt.trials;
  return row.str();
}
bool parse_point_row(const std::string& line, Point& pt) {
  const auto f = split_csv(line);
  if (f.size() < 9) return false;
  try {
    pt.coupling = f[0];
    pt.h = std::stod(f[1]) * 1e-6;
    pt.kl_scale = std::stod(f[2]);
    pt.kb_scale = std::stod(f[3]);
    pt.stable = std::stod(f[4]);
    pt.unstable = std::stod(f[5]);
    pt.cap = std::stod(f[6]);
    pt.cause = f[7];
    pt.trials = std::stoi(f[8]);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

// A file written whole or not at all: to NAME.tmp.<pid>, then renamed (a stopped map never leaves
// half a point behind).
void write_whole(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path tmp = file.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream f(tmp);
    f << text;
    if (!f.flush()) throw std::runtime_error(tmp.string() + ": cannot write (disk full?)");
  }
  std::filesystem::rename(tmp, file);
}

// A point's own file (points/<case>.csv: the header and its row), or false if absent/unreadable.
bool read_point_file(const std::filesystem::path& file, Point& pt) {
  std::ifstream f(file);
  std::string header, line;
  return std::getline(f, header) && header == kPointHeader && std::getline(f, line) && parse_point_row(line, pt);
}

bool read_extremes(const std::filesystem::path& file, std::vector<Extreme>& out) {
  std::ifstream b(file);
  std::string line;
  if (!std::getline(b, line) || line != kExtremeHeader) return false;
  std::vector<Extreme> read;
  while (std::getline(b, line)) {
    const auto f = split_csv(line);
    if (f.size() < 8) return false;
    Extreme e;
    e.name = f[0];
    e.what = f[1];
    e.coupling = f[2];
    try {
      e.dt = std::stod(f[3]);
      e.end = std::stod(f[4]);
      e.wall_seconds = std::stod(f[7]);
    } catch (const std::exception&) {
      return false;
    }
    e.stable = f[5] == "1";
    e.outcome = f[6];
    read.push_back(e);
  }
  out = read;
  return !out.empty();
}

std::string extremes_csv(const std::vector<Extreme>& extremes) {
  std::ostringstream ex;
  ex << kExtremeHeader << "\n";
  for (const Extreme& e : extremes)
    ex << "\"" << e.name << "\",\"" << e.what << "\"," << e.coupling << "," << e.dt << "," << e.end << "," << e.stable << ",\""
       << e.outcome << "\"," << e.wall_seconds << "\n";
  return ex.str();
}

// The map's points in the order of its tables: per coupling and h, the k_l then the k_b scales.
struct PointCase {
  std::string name, coupling;
  double h = 0, kl = 1, kb = 1;
};
std::vector<PointCase> point_cases(const Params& p) {
  std::vector<PointCase> out;
  auto add = [&](const std::string& c, double h, double kl, double kb) {
    char name[96];
    std::snprintf(name, sizeof name, "%s_h%gum_kl%g_kb%g", c.c_str(), h * 1e6, kl, kb);
    out.push_back({name, c, h, kl, kb});
  };
  for (const std::string& c : p.couplings)
    for (double h : p.mesh_sizes) {
      for (double kl : p.kl_scales) add(c, h, kl, 1);
      for (double kb : p.kb_scales) add(c, h, 1, kb);
    }
  return out;
}

constexpr const char* kExtremesCase = "extremes";

}  // namespace

std::vector<std::string> cases(const Params& p) {
  std::vector<std::string> names{kExtremesCase};  // (the longest first)
  for (const PointCase& c : point_cases(p)) names.push_back(c.name);
  return names;
}

namespace {
void fill_quick_record(Results& res);
}  // namespace

// Each point is a case of its own (points/<case>.csv) and the extreme cases one more
// (extremes.csv), so that GNU parallel or a Slurm array can run them apart (--only) and a stopped
// map loses at most the points in progress; --reuse and --resume read the cases already written,
// --collect reads them and computes none (a case not written: not run, named in check.md).
Results run(const Params& p) {
  namespace fs = std::filesystem;
  const fs::path out(p.out_dir), points = out / "points";
  fs::create_directories(points);
  case_runner::require_case(cases(p), p.only, "stability_map");
  const bool read_back = p.reuse || p.resume || p.collect;
  Results res;
  for (const PointCase& c : point_cases(p)) {
    if (!p.only.empty() && c.name != p.only) continue;
    const fs::path file = points / (c.name + ".csv");
    Point pt;
    if (!(read_back && read_point_file(file, pt))) {
      if (p.collect) {
        res.not_run.push_back(c.name);
        continue;
      }
      pt = bisect(p, c.coupling, c.h, c.kl, c.kb);
      write_whole(file, std::string(kPointHeader) + "\n" + point_row(pt) + "\n");
      if (p.progress)
        std::printf("  %-14s h %.4g um  kl x%-6g kb x%-6g  stable %.3g s  unstable %s  (%d trials)\n", pt.coupling.c_str(), pt.h * 1e6,
                    pt.kl_scale, pt.kb_scale, pt.stable,
                    pt.unstable > 0 ? (std::to_string(pt.unstable) + " s, " + pt.cause).c_str() : ">= cap", pt.trials);
    }
    res.points.push_back(pt);
  }
  if (p.only.empty() || p.only == kExtremesCase) {
    if (!(read_back && read_extremes(out / "extremes.csv", res.extremes))) {
      if (p.collect) {
        res.not_run.push_back(kExtremesCase);
      } else {
        res.extremes = extremes(p);
        write_whole(out / "extremes.csv", extremes_csv(res.extremes));
      }
    }
  }
  if (!p.only.empty()) return res;
  std::string map = std::string(kPointHeader) + "\n";
  for (const Point& pt : res.points) map += point_row(pt) + "\n";
  write_whole(out / "stability_map.csv", map);  // the whole map, for plot.gp
  write_tables(p, res);
  if (p.quick) fill_quick_record(res);
  return res;
}

namespace {

// The quick map's own numbers: each point's stable Δt and each extreme case's outcome.
void fill_quick_record(Results& res) {
  for (const Point& pt : res.points) {
    char id[96], q[160];
    std::snprintf(id, sizeof id, "%s_h%g_kl%g_kb%g", pt.coupling.c_str(), pt.h * 1e6, pt.kl_scale, pt.kb_scale);
    std::snprintf(q, sizeof q, "%s: largest stable dt, h = %g um, k_l x %g, k_b x %g", pt.coupling.c_str(), pt.h * 1e6, pt.kl_scale,
                  pt.kb_scale);
    res.quick_record[id] = {q, "s", pt.stable};
  }
  for (const Extreme& e : res.extremes) res.quick_record["extreme " + e.name] = {"extreme case ran through (1) or stopped (0): " + e.name, "", e.stable ? 1.0 : 0.0};
}

}  // namespace

void write_tables(const Params& p, const Results& res) {
  // The report's table: both couplings side by side, and the extreme cases.
  std::ofstream md(p.out_dir + "/check.md");
  md << "The study publishes no stability numbers: this table is ours (no tolerance, no verdict).\n\n"
     << "| h (um) | k_l x | k_b x | explicit: stable / unstable Δt (s) | semi-implicit: stable Δt (s) | ratio | semi-implicit limited by | "
        "semi-implicit, extrapolated Lie scheme: stable Δt (s) |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  auto same_point = [](const Point& a, const Point& b) { return a.h == b.h && a.kl_scale == b.kl_scale && a.kb_scale == b.kb_scale; };
  auto limited_by = [](const Point& pt) { return pt.unstable > 0 ? pt.cause.substr(0, pt.cause.find(" (")) : std::string("the advective cap (Q = 4)"); };
  for (const Point& e : res.points) {
    if (e.coupling != "explicit") continue;
    for (const Point& si : res.points) {
      if (si.coupling != "semi-implicit" || !same_point(si, e)) continue;
      std::string extrapolated = "not run";
      for (const Point& x : res.points)
        if (x.coupling == case_runner::kExtrapolatedKind && same_point(x, e)) {
          char b[200];
          std::snprintf(b, sizeof b, "%s%.2e%s%s", x.unstable > 0 ? "" : ">= ", x.stable, x.unstable > 0 ? ", limited by " : "",
                        x.unstable > 0 ? limited_by(x).c_str() : "");
          extrapolated = b;
        }
      char row[640];
      std::snprintf(row, sizeof row, "| %g | %g | %g | %.2e / %.2e | %s%.2e | %.0f | %s | %s |\n", e.h * 1e6, e.kl_scale, e.kb_scale, e.stable,
                    e.unstable, si.unstable > 0 ? "" : ">= ", si.stable, si.stable / e.stable, limited_by(si).c_str(), extrapolated.c_str());
      md << row;
    }
  }
  md << "\nExtreme cases (stiff membranes, crowds, Re0 far from the study's, h halved), semi-implicit coupling, h = 0.25 um:\n\n| case | set-up | Δt (s) | outcome | wall (s) |\n|---|---|---|---|---|\n";
  for (const Extreme& e : res.extremes) {
    char row[400];
    std::snprintf(row, sizeof row, "| %s | %s | %.3g | %s | %.1f |\n", e.name.c_str(), e.what.c_str(), e.dt, e.outcome.c_str(), e.wall_seconds);
    md << row;
  }
  if (!res.not_run.empty()) {
    md << "\nNot run (--collect: no finished case in " << p.out_dir << "): " << res.not_run.size() << " of " << cases(p).size()
       << " cases:";
    for (const std::string& c : res.not_run) md << " " << c;
    md << ".\n";
  }
}

}  // namespace rbc::stability_map
