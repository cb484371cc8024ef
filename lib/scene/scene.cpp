#include "scene/scene.hpp"

#include "io/provenance.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <map>

#include <toml++/toml.h>

#include "semi_implicit/step_mobility.hpp"
#include "membrane/cell.hpp"
#include "membrane/membrane_crossing.hpp"
#include "membrane/shape_preparation.hpp"

namespace rbc {

namespace {

// The keys a scene may hold, table by table.
struct TableSpec {
  std::string name;
  std::vector<std::string> keys;
};
const std::vector<TableSpec>& schema() {
  static const std::vector<TableSpec> s = {
      {"fluid", {"density", "viscosity"}},
      {"channel", {"length", "height", "mesh_size", "reynolds", "body_force", "wall_velocity"}},
      {"time", {"dt", "end", "coupling", "advection_substeps", "projection", "scheme", "extrapolate_pressure"}},
      {"solver", {"pressure_preconditioner", "cg_tolerance", "cg_max_iterations", "coupling_tolerance", "obstacle_tolerance", "obstacle_preconditioner", "disk_tolerance", "disk_boundary_spacing"}},
      {"output", {"every", "vtk", "vtk_every", "snapshots", "fields", "frames"}},
      {"contact", {"range", "strength"}},
      {"repulsion", {"range", "strength"}},
      {"membrane", {"nodes", "radius", "kl", "kb", "ks", "units", "area_penalty"}},
  };
  return s;
}
// Scene tables (paper/scene_keys.md) that need parts of the method this version does not have yet.
const std::vector<std::string> kNotYet = {};
const std::vector<std::string> kCellKeys = {"center", "swelling_ratio", "angle", "kb_scale"};
const std::vector<std::string> kObstacleKeys = {"x", "y", "wall"};
const std::vector<std::string> kDiskKeys = {"center", "radius"};

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string suggestion(const std::string& word, const std::vector<std::string>& options) {
  std::string best;
  std::size_t d = std::string::npos;
  for (const auto& o : options)
    if (std::size_t e = edit_distance(word, o); e < d) { d = e; best = o; }
  std::string all;
  for (const auto& o : options) all += (all.empty() ? "" : ", ") + o;
  if (d <= std::max<std::size_t>(2, word.size() / 3)) return " (did you mean '" + best + "'?; allowed: " + all + ")";
  return " (allowed: " + all + ")";
}

class Reader {
 public:
  Reader(const toml::table& root, std::string source) : root_(root), src_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw SceneError(src_ + ": " + where + ": " + what);
  }

  void check_structure() const {
    std::vector<std::string> tables = {"cell", "obstacle", "disk"};
    for (const auto& t : schema()) tables.push_back(t.name);
    for (auto&& [k, node] : root_) {
      const std::string key(k.str());
      if (std::find(kNotYet.begin(), kNotYet.end(), key) != kNotYet.end())
        fail("[[" + key + "]]", "is not built in this version of rbcflow yet");
      if (key == "cell" || key == "obstacle" || key == "disk") {
        if (!node.is_array_of_tables()) fail("'" + key + "'", "must be an array of tables, written [[" + key + "]]");
        const std::vector<std::string>& allowed = key == "cell" ? kCellKeys : key == "obstacle" ? kObstacleKeys : kDiskKeys;
        int k = 0;
        for (auto&& c : *node.as_array()) {
          for (auto&& [kk, vv] : *c.as_table()) {
            const std::string sub(kk.str());
            if (std::find(allowed.begin(), allowed.end(), sub) == allowed.end())
              fail("[[" + key + "]] " + std::to_string(k) + " " + sub, "unknown key" + suggestion(sub, allowed));
          }
          ++k;
        }
        continue;
      }
      auto it = std::find_if(schema().begin(), schema().end(), [&](const TableSpec& t) { return t.name == key; });
      if (it == schema().end()) fail("'" + key + "'", "unknown table" + suggestion(key, tables));
      if (!node.is_table()) fail("'" + key + "'", "must be a table, written [" + key + "]");
      for (auto&& [kk, vv] : *node.as_table()) {
        const std::string sub(kk.str());
        if (std::find(it->keys.begin(), it->keys.end(), sub) == it->keys.end()) {
          if (key == "solver" && (sub == "coupling_start" || sub == "coupling_blocks" || sub == "coupling_solves"))
            fail("[solver] " + sub, "is no longer a scene key: how the semi-implicit coupling's system is solved is fixed by the "
                                    "library (CouplingOptions, lib/semi_implicit/semi_implicit_coupling.hpp); remove the line");
          fail("[" + key + "] " + sub, "unknown key" + suggestion(sub, it->keys));
        }
      }
    }
  }

  const toml::node* find(const std::string& table, const std::string& key) const {
    if (current_ && table == current_name_) return current_->get(key);
    const toml::node* t = root_.get(table);
    if (!t || !t->is_table()) return nullptr;
    return t->as_table()->get(key);
  }
  // Reads the keys of one [[cell]] entry through the same checks, named "[[cell]] k".
  void enter(const toml::table* t, const std::string& name) const { current_ = t; current_name_ = name; }

  std::vector<double> list(const std::string& table, const std::string& key, const char* unit) const {
    const std::string where = "[" + table + "] " + key;
    std::vector<double> v;
    const toml::node* n = find(table, key);
    if (!n) return v;
    const toml::array* a = n->as_array();
    if (!a) fail(where, std::string("must be an array of numbers (in ") + unit + ")");
    for (auto&& e : *a) {
      if (!e.is_number()) fail(where, std::string("must be an array of numbers (in ") + unit + ")");
      const double x = e.value<double>().value();
      if (!std::isfinite(x) || x < 0) fail(where, "must hold finite, non-negative numbers");
      v.push_back(x);
    }
    std::sort(v.begin(), v.end());
    return v;
  }
  bool has(const std::string& table, const std::string& key) const { return find(table, key) != nullptr; }

  // A real number in (lo, hi] or [lo, hi] (finite), with its unit for messages.
  double number(const std::string& table, const std::string& key, const char* unit, double lo, double hi,
                bool open_low, std::optional<double> fallback = std::nullopt) const {
    const std::string where = (current_ && table == current_name_ ? table : "[" + table + "]") + " " + key;
    const toml::node* n = find(table, key);
    if (!n) {
      if (fallback) return *fallback;
      fail(where, std::string("missing required key (a number, in ") + unit + ")");
    }
    if (!n->is_number()) fail(where, std::string("must be a number (in ") + unit + "), not " + type_name(*n));
    const double v = n->value<double>().value();
    std::ostringstream range;
    range << (open_low ? "(" : "[") << lo << ", " << hi << "]";
    if (!std::isfinite(v) || (open_low ? v <= lo : v < lo) || v > hi) {
      std::ostringstream s;
      s << "= " << v << " " << unit << " is out of range; allowed: " << range.str() << " " << unit;
      fail(where, s.str());
    }
    return v;
  }

  long integer(const std::string& table, const std::string& key, long lo, long hi, long fallback) const {
    const std::string where = "[" + table + "] " + key;
    const toml::node* n = find(table, key);
    if (!n) return fallback;
    if (!n->is_integer()) fail(where, "must be an integer, not " + type_name(*n));
    const long v = long(n->value<int64_t>().value());
    if (v < lo || v > hi) fail(where, "= " + std::to_string(v) + " is out of range; allowed: " + std::to_string(lo) + " to " + std::to_string(hi));
    return v;
  }

  std::string word(const std::string& table, const std::string& key, const std::vector<std::string>& allowed,
                   const std::string& fallback) const {
    const std::string where = (current_ && table == current_name_ ? table : "[" + table + "]") + " " + key;
    const toml::node* n = find(table, key);
    if (!n) return fallback;
    if (!n->is_string()) fail(where, "must be a string, not " + type_name(*n));
    const std::string v(n->value<std::string>().value());
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) fail(where, "= \"" + v + "\" is not known" + suggestion(v, allowed));
    return v;
  }

  bool boolean(const std::string& table, const std::string& key, bool fallback) const {
    const toml::node* n = find(table, key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail("[" + table + "] " + key, "must be true or false, not " + type_name(*n));
    return n->value<bool>().value();
  }

  void pair(const std::string& table, const std::string& key, const char* unit, double out[2]) const {
    const std::string where = (current_ && table == current_name_ ? table : "[" + table + "]") + " " + key;
    const toml::node* n = find(table, key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number())
      fail(where, std::string("must be an array of two numbers (in ") + unit + "), e.g. [0.0, 0.0]");
    for (int k = 0; k < 2; ++k) {
      out[k] = (*a)[std::size_t(k)].value<double>().value();
      if (!std::isfinite(out[k])) fail(where, "must hold finite numbers");
    }
  }

  static std::string type_name(const toml::node& n) {
    if (n.is_string()) return "a string";
    if (n.is_boolean()) return "a boolean";
    if (n.is_array()) return "an array";
    if (n.is_table()) return "a table";
    if (n.is_integer()) return "an integer";
    if (n.is_floating_point()) return "a number";
    return "a date or time";
  }

 private:
  const toml::table& root_;
  std::string src_;
  mutable const toml::table* current_ = nullptr;
  mutable std::string current_name_;
};

void apply_override(toml::table& root, const std::string& assignment, const std::string& source) {
  const auto eq = assignment.find('=');
  const std::string path = assignment.substr(0, eq);
  const auto dot = path.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == path.size() ||
      path.find('.', dot + 1) != std::string::npos)
    throw SceneError(source + ": --set " + assignment + ": expected table.key=value, e.g. time.dt=1e-7");
  const std::string table = path.substr(0, dot), key = path.substr(dot + 1), value = assignment.substr(eq + 1);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"v", value}};  // a bare word: take it as a string
  }
  if (!root.contains(table)) root.insert(table, toml::table{});
  toml::table* t = root[table].as_table();
  if (!t) throw SceneError(source + ": --set " + assignment + ": '" + table + "' is not a table");
  t->insert_or_assign(key, *parsed.get("v"));
}

// Ray casting: is p inside the closed polygon r?
bool inside(const Points& r, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, n = r.size(), j = n - 1; i < n; j = i++)
    if ((r[i].y() > p.y()) != (r[j].y() > p.y()) &&
        p.x() < (r[j].x() - r[i].x()) * (p.y() - r[i].y()) / (r[j].y() - r[i].y()) + r[i].x())
      in = !in;
  return in;
}

// Does a node of `inner` lie inside `outer`, taking for each node the periodic image (period L
// in x1) nearest to outer's centroid?
bool any_node_inside(const Points& outer, const Points& inner, double L) {
  const double c = area_centroid(outer).x();
  for (Eigen::Vector2d p : inner) {
    p.x() = nearest_image(p.x(), L, c);
    if (inside(outer, p)) return true;
  }
  return false;
}

bool polygons_overlap(const Points& a, const Points& b, double L) {
  return any_node_inside(a, b, L) || any_node_inside(b, a, L) || membranes_cross(a, b, L).has_value();
}

std::string um(double metres) {
  std::ostringstream o;
  o << metres * 1e6 << " um";
  return o.str();
}

std::string seconds(double s) {
  std::ostringstream o;
  o << s << " s";
  return o.str();
}

// Obstacles: inside the channel, edges on mesh lines, at least 2h thick each way, leaving a passage,
// not overlapping each other, standing on the wall the scene names.
void validate_obstacles(const Reader& r, const Scene& s) {
  const double h = s.mesh_size, L = s.length, H = s.height;
  for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
    const Obstacle& o = s.obstacles[k];
    const std::string name = "[[obstacle]] " + std::to_string(k);
    if (!(o.x[0] >= 0 && o.x[1] <= L * (1 + 1e-12) && o.x[0] < o.x[1]))
      r.fail(name + " x", "= [" + um(o.x[0]) + ", " + um(o.x[1]) + "] must satisfy 0 <= a < b <= L = " + um(L));
    if (!(o.y[0] >= 0 && o.y[1] <= H * (1 + 1e-12) && o.y[0] < o.y[1]))
      r.fail(name + " y", "= [" + um(o.y[0]) + ", " + um(o.y[1]) + "] must satisfy 0 <= c < d <= H = " + um(H));
    for (int axis = 0; axis < 2; ++axis) {
      const double* v = axis == 0 ? o.x : o.y;
      for (int e = 0; e < 2; ++e)
        if (!on_mesh_line(v[e], h))
          r.fail(name + (axis == 0 ? " x" : " y"), "edge " + um(v[e]) + " is not on a mesh line (multiples of h = " + um(h) +
                                                       "); nearest: " + um(nearest_mesh_line(v[e], h)));
      if (v[1] - v[0] < 2 * h * (1 - 1e-9))
        r.fail(name + (axis == 0 ? " x" : " y"), "the obstacle is " + um(v[1] - v[0]) + " thick, thinner than 2h = " + um(2 * h) +
                                                     " (the mesh cannot hold it)");
    }
    if (o.y[1] - o.y[0] > H - 2 * h * (1 - 1e-9))
      r.fail(name + " y", "the obstacle leaves less than 2h = " + um(2 * h) + " of open height: the channel would be shut");
    if (o.wall == "bottom" && o.y[0] > 1e-6 * h)
      r.fail(name + " wall", "= \"bottom\" but the obstacle starts at y = " + um(o.y[0]) + ", not on the bottom wall (y = 0)");
    if (o.wall == "top" && o.y[1] < H - 1e-6 * h)
      r.fail(name + " wall", "= \"top\" but the obstacle ends at y = " + um(o.y[1]) + ", not on the top wall (y = " + um(H) + ")");
  }
  for (std::size_t a = 0; a < s.obstacles.size(); ++a)
    for (std::size_t b = a + 1; b < s.obstacles.size(); ++b) {
      const Obstacle &p = s.obstacles[a], &q = s.obstacles[b];
      const bool y_overlap = p.y[0] < q.y[1] && q.y[0] < p.y[1];
      bool x_overlap = false;
      for (int shift = -1; shift <= 1; ++shift)
        x_overlap = x_overlap || (p.x[0] < q.x[1] + shift * L && q.x[0] + shift * L < p.x[1]);
      if (x_overlap && y_overlap)
        r.fail("[[obstacle]] " + std::to_string(a) + " and " + std::to_string(b), "the obstacles overlap; join them into one");
    }
  // A section whose obstacles leave no open height would shut the channel.
  if (!s.obstacles.empty()) {
    const ObstacleGeometry g(ChannelMesh::make(L, H, h), s.obstacles);
    for (int i = 0; i < g.mesh().nx; ++i)
      if (g.open_height(g.mesh().x(i)) < 2 * h * (1 - 1e-9))
        r.fail("[[obstacle]]", "the obstacles together leave less than 2h of open height at x = " + um(g.mesh().x(i)) +
                                   ": the channel would be shut");
  }
}

// Disks: at least 2h in radius (the multiplier needs nodes inside), inside the channel at least
// one mesh cell from each wall (their boundary points read the velocity bilinearly from the
// interior rows), apart from each other; not yet together with obstacles.
void validate_disks(const Reader& r, const Scene& s) {
  const double h = s.mesh_size, L = s.length, H = s.height;
  if (!s.disks.empty() && !s.obstacles.empty())
    r.fail("[[disk]]", "disks and [[obstacle]] rectangles in one scene are not supported in this version of rbcflow");
  for (std::size_t k = 0; k < s.disks.size(); ++k) {
    const DiskSpec& d = s.disks[k];
    const std::string name = "[[disk]] " + std::to_string(k);
    if (d.radius < 2 * h * (1 - 1e-9)) r.fail(name + " radius", "= " + um(d.radius) + " is below 2h = " + um(2 * h) + " (the mesh cannot hold it)");
    if (!(d.center.x() >= 0 && d.center.x() < L)) r.fail(name + " center", "x = " + um(d.center.x()) + " must lie in [0, L) = [0, " + um(L) + ")");
    if (!(d.center.y() - d.radius >= h * (1 - 1e-9) && d.center.y() + d.radius <= H - h * (1 - 1e-9)))
      r.fail(name + " center", "the disk (x2 from " + um(d.center.y() - d.radius) + " to " + um(d.center.y() + d.radius) +
                                   ") must stay at least one mesh cell h = " + um(h) + " from each wall (0 and " + um(H) + ")");
  }
  for (std::size_t a = 0; a < s.disks.size(); ++a)
    for (std::size_t b = a + 1; b < s.disks.size(); ++b) {
      Eigen::Vector2d d = s.disks[a].center - s.disks[b].center;
      d.x() = nearest_image(d.x(), L);
      if (d.norm() < s.disks[a].radius + s.disks[b].radius + h * (1 - 1e-9))
        r.fail("[[disk]] " + std::to_string(a) + " and " + std::to_string(b), "the disks overlap or are closer than one mesh cell h = " + um(h));
    }
}

// parse_scene's parts, in its order: the TOML text with the overrides, the keys of each table
// (defaults and allowed ranges in the Reader's calls), the bodies' arrays, then the checks that
// need the whole scene.
constexpr double big = 1e300;  // no upper bound beyond the number's own

toml::table read_toml(const std::string& text, const std::string& source, const std::vector<std::string>& overrides) {
  if (text.find('\0') != std::string::npos) throw SceneError(source + ": not a TOML scene file (it holds binary data)");
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source << ":" << e.source().begin.line << ": not valid TOML: " << e.description();
    throw SceneError(s.str());
  }
  for (const auto& o : overrides) apply_override(root, o, source);
  return root;
}

// [fluid], [channel], [time]
void read_flow(const Reader& r, Scene& s) {
  s.fluid.density = r.number("fluid", "density", "kg/m^3", 0, big, true, s.fluid.density);
  s.fluid.viscosity = r.number("fluid", "viscosity", "Pa s", 0, big, true, s.fluid.viscosity);
  s.length = r.number("channel", "length", "m", 0, big, true);
  s.height = r.number("channel", "height", "m", 0, big, true);
  s.mesh_size = r.number("channel", "mesh_size", "m", 0, big, true);
  const bool re = r.has("channel", "reynolds"), bf = r.has("channel", "body_force");
  if (re && bf) r.fail("[channel]", "give either reynolds or body_force, not both");
  if (!re && !bf) r.fail("[channel]", "missing the driving force: give reynolds (cell-free Re0) or body_force (N/m^3)");
  if (re) s.reynolds0 = r.number("channel", "reynolds", "(dimensionless)", -1e6, 1e6, false);
  if (bf) s.body_force = r.number("channel", "body_force", "N/m^3", -big, big, false);
  r.pair("channel", "wall_velocity", "m/s", s.wall_velocity);
  s.dt = r.number("time", "dt", "s", 0, big, true);
  s.end = r.number("time", "end", "s", 0, big, true);
  if (s.end < s.dt) r.fail("[time] end", "must be at least one time step (dt)");
  // The step count is a 64-bit integer (run_scene): far beyond any run's, so a larger end/dt is a
  // unit slip, not a run (a Δt in µs written as s).
  if (s.end / s.dt > kMaxSteps) {
    char b[160];
    std::snprintf(b, sizeof b, "end / dt = %.3g steps, more than %.0e: check the units of [time] dt and end (seconds)", s.end / s.dt, kMaxSteps);
    r.fail("[time]", b);
  }
  s.coupling = r.word("time", "coupling", {"explicit", "semi-implicit"}, s.coupling);
  s.advection_substeps = int(r.integer("time", "advection_substeps", 1, 1000, 1));
  // The pressure's form: the study's by default, the incremental one with obstacles (below).
  s.projection = r.word("time", "projection", {"study", "incremental"}, s.projection);
  s.scheme = r.word("time", "scheme", {"lie", "lie-extrapolated", "bdf2"}, s.scheme);
  s.extrapolate_pressure = r.boolean("time", "extrapolate_pressure", s.extrapolate_pressure);
  if (!s.extrapolate_pressure && s.scheme != "lie-extrapolated")
    r.fail("[time] extrapolate_pressure", "is a choice of scheme = \"lie-extrapolated\" only (the scheme here: \"" + s.scheme + "\")");
}

// [solver]
void read_solver(const Reader& r, Scene& s) {
  s.pressure_preconditioner = r.word("solver", "pressure_preconditioner", {"schur", "laplacian"}, s.pressure_preconditioner);
  s.cg_tolerance = r.number("solver", "cg_tolerance", "(relative residual)", 1e-16, 1e-2, false, s.cg_tolerance);
  s.cg_max_iterations = int(r.integer("solver", "cg_max_iterations", 1, 100000, s.cg_max_iterations));
  s.coupling_tolerance = r.number("solver", "coupling_tolerance", "(relative residual)", 1e-14, 1e-1, false, s.coupling_tolerance);
  s.obstacle_tolerance = r.number("solver", "obstacle_tolerance", "(relative velocity)", 1e-15, 1e-2, false, s.obstacle_tolerance);
  s.obstacle_preconditioner = r.word("solver", "obstacle_preconditioner", {"capacitance", "none"}, s.obstacle_preconditioner);
  s.disk_tolerance = r.number("solver", "disk_tolerance", "(relative velocity)", 1e-15, 1e-2, false, s.disk_tolerance);
  s.disk_boundary_spacing = r.number("solver", "disk_boundary_spacing", "(h)", 1.0, 4.0, false, s.disk_boundary_spacing);
}

// [contact] (the disks') and [repulsion] (the membranes')
void read_contacts(const Reader& r, Scene& s) {
  // The disks' contact force: range 2h unless given (the run stops at a gap below h).
  s.contact_range = r.number("contact", "range", "m", 0, big, true, 2 * s.mesh_size);
  s.contact_strength = r.number("contact", "strength", "N/m", 0, big, false, s.contact_strength);
  if (s.contact_range <= s.mesh_size)
    r.fail("[contact] range", "= " + um(s.contact_range) + " must exceed one mesh cell h = " + um(s.mesh_size) +
                                  " (a disk closer than h to a wall or another disk stops the run)");
  // The membranes' repulsion: range h unless given, within about a mesh cell; off by default.
  s.repulsion_range = r.number("repulsion", "range", "m", 0, 3 * s.mesh_size, true, s.mesh_size);
  s.repulsion_strength = r.number("repulsion", "strength", "N/m", 0, 1.0, false, 0.0);
}

// [output]
void read_output(const Reader& r, Scene& s) {
  s.output_every = r.number("output", "every", "s", 0, big, true, s.sample_interval());  // default: Scene::sample_interval
  s.vtk = r.boolean("output", "vtk", false);
  if (s.output_every < s.dt) r.fail("[output] every", "must be at least one time step (dt)");
  s.vtk_every = r.number("output", "vtk_every", "s", 0, big, true, s.vtk_interval());  // default: Scene::vtk_interval
  if (s.vtk_every < s.sample_interval())
    r.fail("[output] vtk_every", "= " + seconds(s.vtk_every) + " must be at least [output] every = " + seconds(s.sample_interval()) +
                                     " (the ParaView files are written at samples)");
  s.snapshots = r.list("output", "snapshots", "s");
  s.field_snapshots = r.boolean("output", "fields", false);
  s.frames = int(r.integer("output", "frames", 0, kMaxMovieFrames, 0));
}

// [membrane]
void read_membrane(const Reader& r, Scene& s) {
  // Preparing a shape costs ≈ N³ (≈ 20 s at N = 300): larger N would look like a hang.
  s.membrane_nodes = int(r.integer("membrane", "nodes", 8, kMaxMembraneNodes, s.membrane_nodes));
  s.membrane_radius = r.number("membrane", "radius", "m", 0, big, true, s.membrane_radius);
  s.membrane_constants.kl = r.number("membrane", "kl", "(study's units, N m)", 0, big, true, s.membrane_constants.kl);
  s.membrane_constants.kb = r.number("membrane", "kb", "(study's units, N m)", 0, big, false, s.membrane_constants.kb);
  s.membrane_constants.ks = r.number("membrane", "ks", "(study's units, N m)", 0, big, false, s.membrane_constants.ks);
  s.membrane_constants.units = r.word("membrane", "units", {"si", "cgs"}, s.membrane_constants.units);
  s.area_penalty = r.boolean("membrane", "area_penalty", s.area_penalty);
}

// [[cell]], [[obstacle]], [[disk]]
void read_bodies(const toml::table& root, const Reader& r, Scene& s) {
  if (const toml::node* cells = root.get("cell")) {
    int k = 0;
    for (auto&& c : *cells->as_array()) {
      const std::string name = "[[cell]] " + std::to_string(k++);
      r.enter(c.as_table(), name);
      CellSpec cs;
      double center[2] = {NAN, NAN};
      if (!r.has(name, "center")) r.fail(name, "missing required key center = [x, y] (m)");
      r.pair(name, "center", "m", center);
      cs.center = {center[0], center[1]};
      cs.swelling_ratio = r.number(name, "swelling_ratio", "(s*)", 0.0, 1.0, true);
      cs.angle = r.number(name, "angle", "rad", -100.0, 100.0, false, 0.0);
      cs.kb_scale = r.number(name, "kb_scale", "(times [membrane] kb)", 0.0, 1e6, true, 1.0);
      s.cells.push_back(cs);
      r.enter(nullptr, "");
    }
  }

  if (const toml::node* obstacles = root.get("obstacle")) {
    int k = 0;
    for (auto&& o : *obstacles->as_array()) {
      const std::string name = "[[obstacle]] " + std::to_string(k++);
      r.enter(o.as_table(), name);
      Obstacle ob;
      for (const char* key : {"x", "y"}) {
        if (!r.has(name, key)) r.fail(name, std::string("missing required key ") + key + " = [" + (key[0] == 'x' ? "a, b" : "c, d") + "] (m)");
        double* v = key[0] == 'x' ? ob.x : ob.y;
        v[0] = v[1] = NAN;
        r.pair(name, key, "m", v);
      }
      ob.wall = r.word(name, "wall", {"bottom", "top", "none"}, "");
      if (ob.wall == "none") ob.wall.clear();
      s.obstacles.push_back(ob);
      r.enter(nullptr, "");
    }
  }

  // With obstacles the study's pressure form loses flux between the wide and the narrow parts at
  // practical Δt (paper/method/05_fictitious_domain.md): the incremental form is their default.
  if (!r.has("time", "projection") && !s.obstacles.empty()) s.projection = "incremental";

  if (const toml::node* disks = root.get("disk")) {
    int k = 0;
    for (auto&& d : *disks->as_array()) {
      const std::string name = "[[disk]] " + std::to_string(k++);
      r.enter(d.as_table(), name);
      DiskSpec ds;
      double center[2] = {NAN, NAN};
      if (!r.has(name, "center")) r.fail(name, "missing required key center = [x, y] (m)");
      r.pair(name, "center", "m", center);
      ds.center = {center[0], center[1]};
      ds.radius = r.number(name, "radius", "m", 0, big, true);
      s.disks.push_back(ds);
      r.enter(nullptr, "");
    }
  }
}

// The mesh must fit the channel and stay within the size this version accepts.
void validate_mesh(const Reader& r, const Scene& s) {
  // T_2h must exist: ChannelMesh says which side does not fit.
  try {
    const ChannelMesh m = ChannelMesh::make(s.length, s.height, s.mesh_size);
    if (double(m.nx) * (m.ny + 1) > kMaxVelocityNodes) {
      std::ostringstream msg;
      msg << "gives " << m.nx << " x " << m.ny + 1 << " velocity nodes, more than the " << kMaxVelocityNodes
          << " this version accepts (the study's largest mesh has 320 x 161)";
      r.fail("[channel] mesh_size", msg.str());
    }
  } catch (const std::invalid_argument& e) {
    r.fail("[channel] mesh_size", e.what());
  }
}

// Cells: inside the channel, not overlapping each other, an obstacle or a disk.
void validate_cells(const Reader& r, const Scene& s) {
  // Each prepared as the run will prepare it.
  if (!s.cells.empty()) {
    const MembraneModel mm = s.membrane_model();
    std::map<std::pair<double, double>, PreparedShape> shapes;  // by (s*, k_b scale): k_b/k_l enters the shape
    std::vector<Points> placed;
    for (std::size_t k = 0; k < s.cells.size(); ++k) {
      const CellSpec& c = s.cells[k];
      const std::pair<double, double> key{c.swelling_ratio, c.kb_scale};
      if (!shapes.count(key)) shapes.emplace(key, prepare_shape(model_of(mm, c.kb_scale), c.swelling_ratio));
      placed.push_back(place_shape(shapes.at(key), c.center, c.angle));
      for (const auto& p : placed.back())
        if (!(p.y() > 0.0 && p.y() < s.height)) {
          std::ostringstream m;
          m << "the cell reaches outside the channel (a membrane node at x2 = " << p.y() * 1e6
            << " um; the channel spans 0 < x2 < " << s.height * 1e6 << " um)";
          r.fail("[[cell]] " + std::to_string(k), m.str());
        }
    }
    for (std::size_t a = 0; a < placed.size(); ++a)
      for (std::size_t b = a + 1; b < placed.size(); ++b)
        if (polygons_overlap(placed[a], placed[b], s.length))
          r.fail("[[cell]] " + std::to_string(a) + " and " + std::to_string(b), "the cells overlap");
    // No membrane node in (or on) an obstacle, and no obstacle corner inside a cell.
    if (!s.obstacles.empty()) {
      const ObstacleGeometry g(ChannelMesh::make(s.length, s.height, s.mesh_size), s.obstacles);
      for (std::size_t k = 0; k < placed.size(); ++k)
        for (std::size_t o = 0; o < s.obstacles.size(); ++o) {
          const Obstacle& ob = s.obstacles[o];
          const ObstacleGeometry one(g.mesh(), {ob});
          bool hit = false;
          for (const auto& p : placed[k]) hit = hit || one.contains(p.x(), p.y());
          for (double x : ob.x)
            for (double y : ob.y) hit = hit || any_node_inside(placed[k], Points{Eigen::Vector2d(x, y)}, s.length);
          if (hit)
            r.fail("[[cell]] " + std::to_string(k), "the cell starts inside or across [[obstacle]] " + std::to_string(o) +
                                                      "; move its center");
        }
    }
    // No membrane node in (or within h of) a disk, and no disk centre inside a cell.
    for (std::size_t k = 0; k < placed.size(); ++k)
      for (std::size_t d = 0; d < s.disks.size(); ++d) {
        const DiskSpec& disk = s.disks[d];
        bool hit = any_node_inside(placed[k], Points{disk.center}, s.length);
        for (const auto& p : placed[k]) {
          Eigen::Vector2d o = p - disk.center;
          o.x() = nearest_image(o.x(), s.length);
          hit = hit || o.norm() < disk.radius + s.mesh_size;
        }
        if (hit)
          r.fail("[[cell]] " + std::to_string(k), "the cell starts inside, across or within one mesh cell of [[disk]] " + std::to_string(d) +
                                                    "; move its center");
      }
  }
}

// Δt within the advective bound, and the semi-implicit coupling's table within the memory limit.
// The BDF2 scheme: in the incremental form of the pressure, without obstacles or disks.
void validate_time_step(const Reader& r, const Scene& s) {
  if (s.scheme == "bdf2") {
    if (!s.obstacles.empty() || !s.disks.empty())
      r.fail("[time] scheme", "= \"bdf2\" is for channels without [[obstacle]] or [[disk]] in this version of rbcflow "
                              "(step 4's constraints are not derived for it); use \"lie\" or \"lie-extrapolated\"");
    if (s.projection != "incremental")
      r.fail("[time] scheme", "= \"bdf2\" needs [time] projection = \"incremental\" (its step 4 carries the last pressure)");
  }
  // Δt must respect the advective bound of the wave-like step.
  const ChannelFlowParams fp = s.flow_params();
  if (const double bound = advective_dt_bound(fp); s.dt > bound) {
    std::ostringstream m;
    m << "= " << s.dt << " s exceeds the advective bound " << bound << " s (Q * " << kAdvectiveCfl
      << " * h / U_max with U_max = " << cell_free_peak_speed(fp)
      << " m/s, the cell-free peak speed); lower dt or raise [time] advection_substeps";
    r.fail("[time] dt", m.str());
  }
  // The semi-implicit coupling tabulates the step mobility: at most 8 nx (ny − 1)² doubles (every
  // source row; one cell may visit them all), and with several cells its phase average H for the
  // preconditioner (step_mobility.hpp).
  if (s.coupling == "semi-implicit" && !s.cells.empty()) {
    const ChannelMesh mesh = ChannelMesh::make(s.length, s.height, s.mesh_size);  // checked above
    const double nx = mesh.nx, ny = mesh.ny;
    double gib = 8.0 * nx * (ny - 1) * (ny - 1) * 8.0 / (1024.0 * 1024.0 * 1024.0);
    if (s.cells.size() > 1 || !s.obstacles.empty() || !s.disks.empty())  // the GMRES path's preconditioner
      gib += double(StepMobility::phase_average_bytes(mesh, phase_average_extent(s.membrane_model()))) / (1024.0 * 1024.0 * 1024.0);
    if (gib > kMaxMobilityTableGiB) {
      std::ostringstream m;
      m << "= \"semi-implicit\" on this mesh (" << nx << " x " << ny << ") needs a " << gib
        << " GiB mobility table (limit " << kMaxMobilityTableGiB << " GiB); use a coarser [channel] mesh_size or \"explicit\"";
      r.fail("[time] coupling", m.str());
    }
  }
}

}  // namespace

double Scene::fluid_area() const {
  double a = length * height;
  for (const Obstacle& o : obstacles) a -= (o.x[1] - o.x[0]) * (o.y[1] - o.y[0]);
  return a;
}

double Scene::driving_force() const {
  return body_force ? *body_force : body_force_from_reynolds(*reynolds0, fluid, height);
}

int Scene::advection_substeps_for(double dt) const {
  ChannelFlowParams p = flow_params();
  p.advection_substeps = 1;
  return std::max(1, int(std::ceil(dt / advective_dt_bound(p) * (1 - 1e-12))));
}

ChannelFlowParams Scene::flow_params() const {
  ChannelFlowParams p;
  p.fluid = fluid;
  p.length = length;
  p.height = height;
  p.mesh_size = mesh_size;
  p.body_force = driving_force();
  p.wall_velocity[0] = wall_velocity[0];
  p.wall_velocity[1] = wall_velocity[1];
  p.dt = dt;
  p.advection_substeps = advection_substeps;
  p.preconditioner = parse_pressure_preconditioner(pressure_preconditioner);
  p.cg_tolerance = cg_tolerance;
  p.cg_max_iterations = cg_max_iterations;
  p.incremental_pressure = projection == "incremental";
  p.bdf2 = scheme == "bdf2";
  return p;
}

Scene parse_scene(const std::string& text, const std::string& source, const std::vector<std::string>& overrides) {
  const toml::table root = read_toml(text, source, overrides);
  const Reader r(root, source);
  r.check_structure();
  Scene s;
  s.source = source;
  read_flow(r, s);
  read_solver(r, s);
  read_contacts(r, s);
  read_output(r, s);
  read_membrane(r, s);
  read_bodies(root, r, s);
  validate_mesh(r, s);
  validate_obstacles(r, s);
  validate_disks(r, s);
  validate_cells(r, s);
  validate_time_step(r, s);
  return s;
}

Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path, overrides);
}

namespace {
// A TOML float that reads back to the same double.
std::string toml_number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  std::string t = b;
  if (t.find_first_of(".eEn") == std::string::npos) t += ".0";  // "1" would be a TOML integer
  return t;
}
}  // namespace

std::vector<std::string> scene_keys() {
  std::vector<std::string> keys;
  for (const TableSpec& t : schema())
    for (const std::string& k : t.keys) keys.push_back(t.name + "." + k);
  for (const auto& [table, list] : {std::pair{"cell", &kCellKeys}, std::pair{"obstacle", &kObstacleKeys}, std::pair{"disk", &kDiskKeys}})
    for (const std::string& k : *list) keys.push_back(std::string(table) + "." + k);
  return keys;
}

std::string scene_to_toml(const Scene& s) {
  std::ostringstream o;
  const auto num = toml_number;
  o << "# written by rbcflow code " << code_id() << " from " << s.source << "\n";
  o << "[fluid]\ndensity = " << num(s.fluid.density) << "\nviscosity = " << num(s.fluid.viscosity) << "\n";
  o << "[channel]\nlength = " << num(s.length) << "\nheight = " << num(s.height) << "\nmesh_size = " << num(s.mesh_size) << "\n";
  if (s.reynolds0) o << "reynolds = " << num(*s.reynolds0) << "\n";
  if (s.body_force) o << "body_force = " << num(*s.body_force) << "\n";
  o << "wall_velocity = [" << num(s.wall_velocity[0]) << ", " << num(s.wall_velocity[1]) << "]\n";
  o << "[time]\ndt = " << num(s.dt) << "\nend = " << num(s.end) << "\ncoupling = \"" << s.coupling
    << "\"\nadvection_substeps = " << s.advection_substeps << "\nprojection = \"" << s.projection << "\"\n";
  if (s.scheme != "lie") o << "scheme = \"" << s.scheme << "\"\n";  // (the study's scheme: the line as before it existed)
  if (!s.extrapolate_pressure) o << "extrapolate_pressure = false\n";  // (likewise)
  o << "[solver]\npressure_preconditioner = \"" << s.pressure_preconditioner << "\"\ncg_tolerance = " << num(s.cg_tolerance)
    << "\ncg_max_iterations = " << s.cg_max_iterations << "\ncoupling_tolerance = " << num(s.coupling_tolerance) << "\nobstacle_tolerance = " << num(s.obstacle_tolerance)
    << "\nobstacle_preconditioner = \"" << s.obstacle_preconditioner << "\"\ndisk_tolerance = " << num(s.disk_tolerance) << "\n";
  if (s.disk_boundary_spacing != 1.0) o << "disk_boundary_spacing = " << num(s.disk_boundary_spacing) << "\n";  // (as the scheme line)
  o << "[contact]\nrange = " << num(s.contact_range > 0 ? s.contact_range : 2 * s.mesh_size) << "\nstrength = " << num(s.contact_strength) << "\n";
  o << "[repulsion]\nrange = " << num(s.repulsion_range > 0 ? s.repulsion_range : s.mesh_size) << "\nstrength = " << num(s.repulsion_strength) << "\n";
  o << "[output]\nevery = " << num(s.sample_interval()) << "\nvtk = " << (s.vtk ? "true" : "false") << "\nvtk_every = " << num(s.vtk_interval())
    << "\nsnapshots = [";
  for (std::size_t k = 0; k < s.snapshots.size(); ++k) o << (k ? ", " : "") << num(s.snapshots[k]);
  o << "]\nfields = " << (s.field_snapshots ? "true" : "false") << "\nframes = " << s.frames << "\n";
  o << "[membrane]\nnodes = " << s.membrane_nodes << "\nradius = " << num(s.membrane_radius) << "\nkl = "
    << num(s.membrane_constants.kl) << "\nkb = " << num(s.membrane_constants.kb) << "\nks = " << num(s.membrane_constants.ks)
    << "\nunits = \"" << s.membrane_constants.units << "\"\narea_penalty = " << (s.area_penalty ? "true" : "false") << "\n";
  for (const CellSpec& c : s.cells)
    o << "[[cell]]\ncenter = [" << num(c.center.x()) << ", " << num(c.center.y()) << "]\nswelling_ratio = "
      << num(c.swelling_ratio) << "\nangle = " << num(c.angle) << "\nkb_scale = " << num(c.kb_scale) << "\n";
  for (const Obstacle& b : s.obstacles)
    o << "[[obstacle]]\nx = [" << num(b.x[0]) << ", " << num(b.x[1]) << "]\ny = [" << num(b.y[0]) << ", " << num(b.y[1])
      << "]\nwall = \"" << (b.wall.empty() ? "none" : b.wall) << "\"\n";
  for (const DiskSpec& d : s.disks)
    o << "[[disk]]\ncenter = [" << num(d.center.x()) << ", " << num(d.center.y()) << "]\nradius = " << num(d.radius) << "\n";
  return o.str();
}

}  // namespace rbc
