#include "scene/run_scene.hpp"

#include <array>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "diagnostics/flow_diagnostics.hpp"
#include "io/checkpoint.hpp"
#include "io/provenance.hpp"
#include "io/progress.hpp"
#include "scene/movie_frames.hpp"
#include "scene/vtk_output.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace rbc {

namespace fs = std::filesystem;

namespace {

// The files a run writes into its folder (run_scene, RunOutputs, VtkSeries), by name or pattern.
bool is_run_file(const std::string& name) {
  // (Not scene.toml: the new run writes its own over it, and a user's scene file may bear the name.)
  // code_id: a kept run's label (paper/keep_evidence.sh), which must not stay beside a new run.
  for (const char* f : {"checkpoint.bin", "checkpoint.bin.prev", "series.csv", "summary.json", "snapshots.dat", "frames.dat",
                        "profile.csv", "membranes_final.dat", "vtk", "code_id"})
    if (name == f) return true;
  return name.rfind("field_", 0) == 0 || name.rfind("checkpoint.bin.", 0) == 0;  // fields, temporaries
}

// The folder's lock for the run's life: flock on DIR/.lock (released when the process ends, also
// by a crash), holding the pid of its owner for the message.
class FolderLock {
 public:
  explicit FolderLock(const fs::path& dir) {
    const fs::path path = dir / ".lock";
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw OutputError(path.string() + ": cannot create the folder's lock (" + std::strerror(errno) + ")");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      char owner[32] = {0};
      const ::ssize_t n = ::pread(fd_, owner, sizeof owner - 1, 0);
      ::close(fd_);
      throw OutputError(dir.string() + ": another rbcflow process is running in this folder (pid " + (n > 0 ? std::string(owner, std::size_t(n)) : "?") +
                        "); give each run its own --out");
    }
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {}  // (the pid is for the message only)
  }
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);  // (releases the lock)
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// A fresh run's folder: another run's files cleared, or (refuse) the run refused.
void clear_other_run(const fs::path& dir, bool refuse) {
  std::vector<fs::path> old;
  for (const auto& e : fs::directory_iterator(dir))
    if (is_run_file(e.path().filename().string())) old.push_back(e.path());
  if (old.empty()) return;
  if (refuse)
    throw SceneError(dir.string() + ": holds another run (" + old.front().filename().string() +
                     (old.size() > 1 ? " and " + std::to_string(old.size() - 1) + " more" : "") +
                     "); give --overwrite to clear it, rbcflow resume to continue it, or another --out");
  for (const fs::path& p : old) fs::remove_all(p);
}

}  // namespace

void prepare_output_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw SceneError(dir + ": cannot create the output folder (" + ec.message() + ")");
  const fs::path probe = fs::path(dir) / ".rbcflow-write-test";
  {
    std::ofstream f(probe);
    if (!f) throw SceneError(dir + ": the output folder is not writable");
  }
  fs::remove(probe, ec);
}

namespace {

// Whether the semi-implicit coupling solves its cells' system by GMRES, whose start and
// tolerance then shape the run: several cells, or one in a fluid that obstacles or disks make
// uneven along x1 (its own block is then only a preconditioner: semi_implicit_coupling.hpp).
bool coupling_by_gmres(const Scene& s) {
  return s.coupling == "semi-implicit" && (s.cells.size() > 1 || (!s.cells.empty() && (!s.obstacles.empty() || !s.disks.empty())));
}

// Capillary numbers of the membrane in the cell-free flow (wall shear rate γ̇ = 6 U0 / H):
//   stretching  Ca_l = μ γ̇ R0 l0 / k_l    (viscous force on a spring over its elastic force)
//   bending     Ca_b = μ γ̇ R0³ / (k_b l0 / 4)
void print_membrane_header(const Scene& s, const MembraneModel& m) {
  const double U0 = s.driving_force() * s.height * s.height / (12 * s.fluid.viscosity);
  const double shear = 6 * U0 / s.height, l0 = m.rest_length(), mu = s.fluid.viscosity;
  std::fprintf(stderr,
               "rbcflow: membrane units '%s': k_l = %.3g J/m, k_b = %.3g J/m, k_s = %.3g J/m; wall shear rate %.4g 1/s; "
               "capillary numbers Ca_l = mu*gamma*R0*l0/k_l = %.3g, Ca_b = mu*gamma*R0^3/(k_b*l0/4) = %.3g\n",
               s.membrane_constants.units.c_str(), m.kl, m.kb, m.ks, shear, mu * shear * m.radius * l0 / m.kl,
               mu * shear * std::pow(m.radius, 3) / (m.kb * l0 / 4));
}

// The velocity field for gnuplot: x, y (m), |u|, u1, u2 (m/s), one block per row of nodes.
void write_field(const fs::path& path, const ChannelMesh& m, const VelocityField& u, double t) {
  std::ofstream f(path);
  f << "# t = " << t << " s; x (m), y (m), |u|, u1, u2 (m/s)\n";
  f.precision(8);
  for (int j = 0; j <= m.ny; ++j) {
    for (int i = 0; i <= m.nx; ++i) {  // i = nx repeats column 0 (periodic), so the map spans [0, L]
      const std::size_t k = m.v(i, j);
      f << m.x(i) << " " << m.y(j) << " " << std::hypot(u.u1[k], u.u2[k]) << " " << u.u1[k] << " " << u.u2[k] << "\n";
    }
    f << "\n";
  }
}

void write_membranes(std::ofstream& f, const std::vector<Cell>& cells, double t) {
  f << "# t = " << t << " s; x1 (m), x2 (m) of each cell's nodes, the first repeated\n";
  for (std::size_t k = 0; k < cells.size(); ++k) {
    f << "# cell " << k << "\n";
    for (const auto& p : cells[k].nodes) f << p.x() << " " << p.y() << "\n";
    f << cells[k].nodes.front().x() << " " << cells[k].nodes.front().y() << "\n\n";
  }
  f << "\n";
}

// SIGINT and SIGTERM set a flag that the runs check after every step; the handlers are
// installed while at least one run is going (the experiments run two in one process).
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

class StopSignals {
 public:
  StopSignals() {
    std::lock_guard<std::mutex> g(lock());
    if (users()++ > 0) return;
    g_stop_signal = 0;
    struct sigaction a {};
    a.sa_handler = on_stop_signal;
    sigemptyset(&a.sa_mask);
    sigaction(SIGINT, &a, &old_int());
    sigaction(SIGTERM, &a, &old_term());
  }
  ~StopSignals() {
    std::lock_guard<std::mutex> g(lock());
    if (--users() > 0) return;
    sigaction(SIGINT, &old_int(), nullptr);
    sigaction(SIGTERM, &old_term(), nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  static std::mutex& lock() { static std::mutex m; return m; }
  static int& users() { static int n = 0; return n; }
  static struct sigaction& old_int() { static struct sigaction a {}; return a; }
  static struct sigaction& old_term() { static struct sigaction a {}; return a; }
};

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

// The run's own bookkeeping that a checkpoint must carry for the outputs to continue exactly.
struct RunState {
  std::int64_t series_bytes = 0, snapshot_bytes = 0, frame_bytes = 0;  // output file sizes at the checkpoint
  double u_sum = 0;                                   // mean-velocity average in progress
  std::int64_t u_count = 0;
  double last_mean = 0;
  double nodal_sum = 0, last_nodal = 0;               // the same for the nodal mean U_n
  std::int64_t next_snapshot = 0, vtk_count = 0, next_frame = 0;
  double wall_seconds = 0;  // spent before this session

  // The output files whose lengths the checkpoint records (0: the file is not written).
  std::array<std::pair<const char*, std::int64_t>, 3> output_lengths() const {
    return {{{"series.csv", series_bytes}, {"snapshots.dat", snapshot_bytes}, {"frames.dat", frame_bytes}}};
  }

  void save(CheckpointWriter& w) const {
    w.put(series_bytes);
    w.put(snapshot_bytes);
    w.put(u_sum);
    w.put(u_count);
    w.put(last_mean);
    w.put(nodal_sum);
    w.put(last_nodal);
    w.put(next_snapshot);
    w.put(vtk_count);
    w.put(frame_bytes);
    w.put(next_frame);
    w.put(wall_seconds);
  }
  static RunState load(CheckpointReader& r) {
    RunState s;
    s.series_bytes = r.get_int();
    s.snapshot_bytes = r.get_int();
    s.u_sum = r.get_double();
    s.u_count = r.get_int();
    s.last_mean = r.get_double();
    s.nodal_sum = r.get_double();
    s.last_nodal = r.get_double();
    s.next_snapshot = r.get_int();
    s.vtk_count = r.get_int();
    s.frame_bytes = r.get_int();
    s.next_frame = r.get_int();
    s.wall_seconds = r.get_double();
    return s;
  }
};

// The scene's TOML without comment lines (the first names where the scene was read from).
std::vector<std::string> scene_lines(const std::string& toml) {
  std::vector<std::string> lines;
  std::istringstream in(toml);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l[0] != '#') lines.push_back(l);
  return lines;
}

// Header of every checkpoint: the code that wrote it (io/provenance.hpp), scene source and TOML,
// thread count.
struct CheckpointHeader {
  std::string code, source, scene_toml;
  std::int64_t threads = 0;
};

// Reads the header; a checkpoint written by other code is refused (its state need not be this
// code's: a run must not continue with other arithmetic than it started with) unless any_code
// (rbcflow resume --any-code), which names both codes on stderr.
CheckpointHeader read_header(CheckpointReader& r, bool any_code, bool announce = true) {
  CheckpointHeader h;
  h.code = r.get_string();
  if (h.code != code_id()) {
    if (!any_code)
      throw CheckpointError(r.path() + ": written by code " + h.code + ", this is code " + code_id() +
                            "; rerun the scene from the start, resume with the build of that code, or accept it with --any-code");
    if (announce) std::fprintf(stderr, "rbcflow: warning: %s was written by code %s, this is code %s: continued as asked (--any-code); the run "
                 "mixes the arithmetic of two codes\n", r.path().c_str(), h.code.c_str(), code_id());
  }
  h.source = r.get_string();
  h.scene_toml = r.get_string();
  h.threads = r.get_int();
  return h;
}

// Tries each checkpoint of dir, newest first, with use(reader); the first that use() accepts
// (returns without CheckpointError) wins. Where a newer one was refused the reason is printed
// (announce) before the older one is used; where none is usable, CheckpointError with every reason.
template <class Use>
auto with_newest_usable_checkpoint(const fs::path& dir, Use use, bool announce = true) {
  const fs::path newest = dir / "checkpoint.bin", previous = dir / "checkpoint.bin.prev";
  if (!has_checkpoint(dir.string())) throw CheckpointError(dir.string() + ": no checkpoint to resume from (checkpoint.bin)");
  std::string why;
  for (const fs::path& p : {newest, previous}) {
    if (!fs::exists(p)) {
      why += (why.empty() ? "" : "; ") + p.string() + ": missing";
      continue;
    }
    try {
      CheckpointReader r(p.string());
      auto result = use(r);
      if (p == previous && announce) std::fprintf(stderr, "rbcflow: warning: %s; resuming from %s\n", why.c_str(), p.c_str());
      return result;
    } catch (const CheckpointError& e) {
      why += (why.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  throw CheckpointError(why);
}

void write_checkpoint(const fs::path& dir, const Scene& scene, const Simulation& sim, const RunState& st) {
  CheckpointWriter w;
  w.put(std::string(code_id()));
  w.put(scene.source);
  w.put(scene_to_toml(scene));
  w.put(std::int64_t(omp_get_max_threads()));
  sim.save(w);
  st.save(w);
  w.commit((dir / "checkpoint.bin").string());
}

}  // namespace

int default_threads() {
  auto env = [](const char* name) { const char* v = std::getenv(name); return v && *v ? std::string(v) : std::string(); };
  if (const std::string n = env("SLURM_CPUS_PER_TASK"); !n.empty()) {
    const int k = std::atoi(n.c_str());
    if (k >= 1) return k;
  }
  if (!env("PARALLEL_SEQ").empty() || !env("SLURM_ARRAY_TASK_ID").empty()) return 1;
  return omp_get_max_threads();
}

bool has_checkpoint(const std::string& dir) {
  return fs::exists(fs::path(dir) / "checkpoint.bin") || fs::exists(fs::path(dir) / "checkpoint.bin.prev");
}

Scene checkpoint_scene(const std::string& dir, bool any_code) {
  // (Quietly: the resume that follows reads the same checkpoint and says what it takes.)
  return with_newest_usable_checkpoint(dir, [&](CheckpointReader& r) {
    const CheckpointHeader h = read_header(r, any_code, false);
    try {
      Scene s = parse_scene(h.scene_toml, r.path() + " (its scene)");
      s.source = h.source;
      return s;
    } catch (const SceneError& e) {
      throw CheckpointError(r.path() + ": the scene stored in it is not valid: " + e.what());
    }
  }, false);
}

void load_checkpoint(const std::string& dir, Simulation& sim) {
  with_newest_usable_checkpoint(dir, [&](CheckpointReader& r) {
    read_header(r, false);
    sim.load(r);
    return 0;
  });
}

namespace {

// Resuming: the newest checkpoint in out that is whole, of this scene and code, and whose outputs
// (series.csv, snapshots.dat, frames.dat) are at least as long as it recorded, loaded into sim; the
// outputs are cut back to their lengths at that checkpoint. A newer checkpoint that fails any of
// these (a crash between a write and its sync, a damaged byte) gives way to checkpoint.bin.prev.
RunState resume_run(const fs::path& out, const Scene& scene, Simulation& sim, bool progress, bool any_code) {
  const RunState resumed = with_newest_usable_checkpoint(out, [&](CheckpointReader& r) {
    const CheckpointHeader h = read_header(r, any_code);
    // Other code may write the same scene in other words (a key added, reordered): read back first.
    std::string stored = h.scene_toml;
    if (any_code && h.code != code_id()) {
      try {
        stored = scene_to_toml(parse_scene(h.scene_toml, r.path() + " (its scene)"));
      } catch (const SceneError& e) {
        throw CheckpointError(r.path() + ": the scene stored in it is not valid for this code: " + e.what());
      }
    }
    const std::vector<std::string> a = scene_lines(stored), b = scene_lines(scene_to_toml(scene));
    if (a != b) {
      std::size_t k = 0;
      while (k < a.size() && k < b.size() && a[k] == b[k]) ++k;
      throw CheckpointError(r.path() + ": written for another scene (checkpoint: '" + (k < a.size() ? a[k] : "(end)") +
                            "', this scene: '" + (k < b.size() ? b[k] : "(end)") + "')");
    }
    if (h.threads != omp_get_max_threads() && progress)
      std::fprintf(stderr, "rbcflow: note: the checkpoint was written with %lld threads, this run has %d: the results "
                   "may differ from an uninterrupted run at round-off level\n", (long long)h.threads, omp_get_max_threads());
    sim.load(r);  // (every value of the state is assigned: an older checkpoint loaded after this one overwrites it whole)
    const RunState st = RunState::load(r);
    if (!r.at_end()) throw CheckpointError(r.path() + ": unexpected data after the run state (written by another version?)");
    for (const auto& [name, bytes] : st.output_lengths()) {
      std::error_code ec;
      const auto size = fs::file_size(out / name, ec);
      if (bytes > 0 && (ec || std::int64_t(size) < bytes))
        throw CheckpointError(r.path() + ": " + name + " is shorter (" + (ec ? std::string("missing") : std::to_string(size) + " bytes") +
                              ") than when it was written (" + std::to_string(bytes) + " bytes)");
    }
    if (progress) std::fprintf(stderr, "rbcflow: resuming %s at t = %.6g s (step %ld) from %s\n", out.string().c_str(), sim.time(), long(sim.steps()), r.path().c_str());
    return st;
  });
  for (const auto& [name, bytes] : resumed.output_lengths())
    if (bytes > 0) fs::resize_file(out / name, std::uintmax_t(bytes));
  return resumed;
}

// Largest relative difference between the wide and the narrow parts' section fluxes that a run
// with obstacles accepts without a warning: an incompressible flow carries the same flux through
// every section. (The incremental form: 0.02 % once started; the study's form at Δt = 1e-6 s in
// the study's constriction: 8.5 %, tests/test_fictitious_domain.cpp.)
constexpr double kFluxMismatchWarning = 0.01;

// The run's output files while it goes: series.csv (a row per sample), the membrane snapshots,
// the velocity fields and VTK files asked for. Its state goes into every checkpoint.
// A stream's writes so far reached their file, or the run stops naming it (OutputError).
void check_written(std::ostream& f, const fs::path& file) {
  if (!f)
    throw OutputError(file.string() + ": cannot write (disk full, or the folder removed?); the run stops with its last checkpoint kept: "
                      "make room, then resume");
}

// A stream's writes so far flushed and synced to the disk, or OutputError naming the file.
void flush_to_disk(std::ofstream& f, const fs::path& file) {
  check_written(f.flush(), file);
  if (!sync_file(file.string()))
    throw OutputError(file.string() + ": cannot sync to the disk (" + std::strerror(errno) + "); the run stops with its last checkpoint kept");
}

class RunOutputs {
 public:
  RunOutputs(const fs::path& out, const Scene& scene, const Simulation& sim, const RunState& resumed, bool fresh)
      : out_(out), scene_(scene), sim_(sim), fluid_area_(scene.fluid_area()), l0_(sim.membrane().rest_length()) {
    series_.open(out / "series.csv", fresh ? std::ios::trunc : std::ios::app);
    series_.precision(10);
    if (!sim.cells().empty()) snapshots_.open(out / "snapshots.dat", fresh ? std::ios::trunc : std::ios::app);
    next_snapshot_ = std::size_t(resumed.next_snapshot);
    if (scene.frames > 0) {
      frames_.open(out / "frames.dat", fresh ? std::ios::trunc : std::ios::app);
      if (fresh) write_frames_header(frames_, scene);
    }
    next_frame_ = int(resumed.next_frame);
    if (scene.vtk) vtk_.emplace(out / "vtk", sim, int(resumed.vtk_count));
    u_sum_ = resumed.u_sum;
    nodal_sum_ = resumed.nodal_sum;
    u_count_ = long(resumed.u_count);
    const MeanVelocities now = mean_velocities(sim.flow().mesh(), sim.flow().velocity());
    last_mean_ = fresh ? now.p1 : resumed.last_mean;
    last_nodal_ = fresh ? now.nodal : resumed.last_nodal;
    if (fresh) write_header();
  }
  // After every step: the mean velocity's running average.
  void after_step() {
    const MeanVelocities now = mean_velocities(sim_.flow().mesh(), sim_.flow().velocity());
    u_sum_ += now.p1;
    nodal_sum_ += now.nodal;
    ++u_count_;
  }
  void sample();
  void snapshots_due();
  void frames_due();
  double last_mean() const { return last_mean_; }
  double last_nodal() const { return last_nodal_; }
  RunState state(double wall_seconds) {
    // On the disk before the checkpoint that records their lengths (a crash of the machine, not
    // only of the process, then leaves them at least that long).
    flush_to_disk(series_, out_ / "series.csv");
    if (snapshots_.is_open()) flush_to_disk(snapshots_, out_ / "snapshots.dat");
    if (frames_.is_open()) flush_to_disk(frames_, out_ / "frames.dat");
    RunState st;
    st.series_bytes = std::int64_t(series_.tellp());
    st.snapshot_bytes = snapshots_.is_open() ? std::int64_t(snapshots_.tellp()) : 0;
    st.u_sum = u_sum_;
    st.u_count = u_count_;
    st.last_mean = last_mean_;
    st.nodal_sum = nodal_sum_;
    st.last_nodal = last_nodal_;
    st.next_snapshot = std::int64_t(next_snapshot_);
    st.vtk_count = vtk_ ? vtk_->written() : 0;
    st.frame_bytes = frames_.is_open() ? std::int64_t(frames_.tellp()) : 0;
    st.next_frame = next_frame_;
    st.wall_seconds = wall_seconds;
    return st;
  }

 private:
  void write_header();
  const fs::path out_;
  const Scene& scene_;
  const Simulation& sim_;
  const double fluid_area_, l0_;  // m², the channel minus obstacles; m, the springs' rest length
  std::ofstream series_, snapshots_, frames_;
  std::size_t next_snapshot_ = 0;
  int next_frame_ = 0;  // the movie's ([output] frames)
  std::optional<VtkSeries> vtk_;  // the ParaView files ([output] vtk)
  // The mean velocity of a sample is its average over the steps since the previous sample
  // (the instantaneous value at t = 0).
  double u_sum_ = 0, last_mean_ = 0;
  double nodal_sum_ = 0, last_nodal_ = 0;  // the nodal mean U_n, averaged the same way
  long u_count_ = 0;
  bool flux_warned_ = false;
};

// Two header lines: the columns' units ("# units: ", SI; "1" for a pure number), then their names.
void RunOutputs::write_header() {
  std::vector<std::pair<std::string, const char*>> columns = {
      {"t", "s"}, {"mean_velocity", "m/s"}, {"reynolds", "1"}, {"hematocrit", "%"}, {"max_speed", "m/s"}, {"cg_iterations", "1"},
      {"coupling_iterations", "1"}, {"nodal_mean_velocity", "m/s"}};
  if (!sim_.cells().empty())
    for (const auto& c : {std::pair{"plasma_flux_velocity", "m/s"}, {"plasma_open_velocity", "m/s"}, {"wall_gap_lower", "m"}, {"wall_gap_upper", "m"}})
      columns.emplace_back(c.first, c.second);
  if (sim_.obstacles())
    for (const auto& c : {std::pair{"wide_velocity", "m/s"}, {"narrow_velocity", "m/s"}, {"wide_flux", "m^2/s"}, {"narrow_flux", "m^2/s"},
                          {"uzawa_iterations", "1"}, {"wide_nodal_velocity", "m/s"}, {"narrow_nodal_velocity", "m/s"}})
      columns.emplace_back(c.first, c.second);
  for (std::size_t k = 0; k < sim_.cells().size(); ++k)
    for (const auto& [q, unit] : {std::pair{"x", "m"}, {"y", "m"}, {"area", "m^2"}, {"perimeter", "m"}, {"area_drift", "1"}, {"max_strain", "1"}})
      columns.emplace_back("cell" + std::to_string(k) + "_" + q, unit);
  for (std::size_t k = 0; k < sim_.disks().size(); ++k)
    for (const auto& [q, unit] : {std::pair{"x", "m"}, {"y", "m"}, {"u", "m/s"}, {"v", "m/s"}, {"omega", "rad/s"}})
      columns.emplace_back("disk" + std::to_string(k) + "_" + q, unit);
  series_ << "# units:";
  for (std::size_t k = 0; k < columns.size(); ++k) series_ << (k ? "," : " ") << columns[k].second;
  series_ << "\n";
  for (std::size_t k = 0; k < columns.size(); ++k) series_ << (k ? "," : "") << columns[k].first;
  series_ << "\n";
}

void RunOutputs::sample() {
  const ChannelFlow& flow = sim_.flow();
  const auto& cells = sim_.cells();
  if (u_count_ > 0) {
    last_mean_ = u_sum_ / u_count_;
    last_nodal_ = nodal_sum_ / u_count_;
  }
  u_sum_ = 0;
  nodal_sum_ = 0;
  u_count_ = 0;
  series_ << sim_.time() << "," << last_mean_ << "," << reynolds_number(last_mean_, scene_.fluid, scene_.height) << ","
          << hematocrit_percent(cells, fluid_area_) << "," << max_speed(flow.velocity()) << "," << sim_.last_cg_iterations() << ","
          << sim_.last_coupling_iterations() << "," << last_nodal_;
  if (!cells.empty()) {  // the plasma alone, at the sample's instant (flow_diagnostics.hpp)
    std::vector<const Points*> membranes;
    for (const Cell& c : cells) membranes.push_back(&c.nodes);
    const PlasmaVelocity pv = plasma_velocity(flow.mesh(), flow.velocity(), membranes);
    const WallGaps gap = wall_gaps(cells, scene_.height);  // the cell-free layer at this instant
    series_ << "," << pv.flux_per_height << "," << pv.over_open_height << "," << gap.lower << "," << gap.upper;
  }
  if (const ObstacleConstraint* ob = sim_.obstacles()) {  // flux over open height, and flux, per part (obstacles.hpp)
    const PartVelocities pv = part_velocities(ob->geometry(), flow.velocity());
    series_ << "," << pv.wide << "," << pv.narrow << "," << pv.wide_flux << "," << pv.narrow_flux << "," << ob->last().iterations << ","
            << pv.wide_nodal << "," << pv.narrow_nodal;
    // From rest, u^{n+1} is far from divergence-free while the flow starts (step 4 does not
    // project): the check waits for the viscous time of the narrow part's half-height.
    const double larger = std::max(std::abs(pv.wide_flux), std::abs(pv.narrow_flux));
    const double settled = scene_.fluid.density * 0.25 * pv.narrow_height * pv.narrow_height / scene_.fluid.viscosity;
    if (!flux_warned_ && sim_.time() >= settled && larger > 0 &&
        std::abs(pv.wide_flux - pv.narrow_flux) > kFluxMismatchWarning * larger) {
      flux_warned_ = true;
      std::fprintf(stderr,
                   "rbcflow: warning: at t = %g s the flux through the narrow part's sections (%.6g m^2/s) differs from the wide "
                   "part's (%.6g m^2/s) by %.2f %% (> %g %%): the flow is not incompressible across the obstacles at this dt "
                   "(%s pressure form; the incremental form holds the flux: paper/method/05_fictitious_domain.md)\n",
                   sim_.time(), pv.narrow_flux, pv.wide_flux, 100 * std::abs(pv.wide_flux - pv.narrow_flux) / larger,
                   100 * kFluxMismatchWarning, scene_.projection.c_str());
    }
  }
  for (const Cell& c : cells) {
    const CellState s = measure_cell(c, l0_);
    series_ << "," << s.centroid.x() << "," << s.centroid.y() << "," << s.area << "," << s.perimeter << "," << s.area_drift << ","
            << s.max_strain;
  }
  for (const Disk& d : sim_.disks())  // centre (m, x1 unwrapped), velocity (m/s), spin (1/s)
    series_ << "," << d.center.x() << "," << d.center.y() << "," << d.velocity.x() << "," << d.velocity.y() << "," << d.angular_velocity;
  series_ << "\n";
  check_written(series_.flush(), out_ / "series.csv");
  if (vtk_) vtk_->sample_due();
}

void RunOutputs::snapshots_due() {
  while (next_snapshot_ < scene_.snapshots.size() && scene_.snapshots[next_snapshot_] <= sim_.time() + 0.5 * scene_.dt) {
    if (!sim_.cells().empty()) {
      write_membranes(snapshots_, sim_.cells(), sim_.time());
      check_written(snapshots_.flush(), out_ / "snapshots.dat");
    }
    if (scene_.field_snapshots)
      write_field(out_ / ("field_" + std::to_string(next_snapshot_) + ".dat"), sim_.flow().mesh(), sim_.flow().velocity(), sim_.time());
    ++next_snapshot_;
  }
}

// Frame k at the first step with t ≥ k end/frames − Δt/2 (scene/movie_frames.hpp).
void RunOutputs::frames_due() {
  if (scene_.frames <= 0 || next_frame_ > scene_.frames || sim_.time() < next_frame_ * scene_.end / scene_.frames - 0.5 * scene_.dt) return;
  write_frame(frames_, sim_);
  check_written(frames_.flush(), out_ / "frames.dat");
  ++next_frame_;
}

// The x1-averaged velocity profile at the end, for plots against the Poiseuille parabola.
void write_profile(const fs::path& path, const ChannelFlow& flow) {
  std::ofstream prof(path);
  prof << "# units: m,m/s,m/s\n" << "y,u1,u2\n";
  prof.precision(10);
  const ChannelMesh& m = flow.mesh();
  for (int jy = 0; jy <= m.ny; ++jy) {
    double a = 0, b = 0;
    for (int i = 0; i < m.nx; ++i) {
      a += flow.velocity().u1[m.v(i, jy)];
      b += flow.velocity().u2[m.v(i, jy)];
    }
    prof << m.y(jy) << "," << a / m.nx << "," << b / m.nx << "\n";
  }
}

// summary.json (its keys: run_scene.hpp; the units are in its "units" entry).
// The resolved scene of a run, from which `rbcflow run <folder>/scene.toml` repeats it.
void write_scene_file(const fs::path& path, const Scene& scene) {
  std::ofstream f(path);
  f << "# The resolved scene of the run in this folder (" << scene.source << "), written by code " << code_id() << ", commit "
    << commit_id() << ":\n#   " << command_line() << "\n# Repeat it: rbcflow run " << path.string() << "\n"
    << scene_to_toml(scene);
  check_written(f.flush(), path);
}

void write_summary(const fs::path& path, const Scene& scene, const Simulation& sim, const RunSummary& s, const std::string& started) {
  const ChannelFlow& flow = sim.flow();
  const auto& cells = sim.cells();
  nlohmann::ordered_json j;
  j["steps"] = s.steps;
  j["t_end"] = s.t_end;
  j["wall_seconds"] = s.wall_seconds;
  j["mean_velocity"] = s.mean_velocity;
  j["mean_velocity_averaging"] = "time average over the last sample interval (output.every)";
  j["reynolds"] = s.reynolds;
  j["nodal_mean_velocity"] = s.nodal_mean_velocity;
  j["hematocrit"] = s.hematocrit;
  j["cells"] = nlohmann::json::array();
  for (const CellState& c : s.cells)
    j["cells"].push_back({{"centroid", {c.centroid.x(), c.centroid.y()}},
                          {"area", c.area},
                          {"perimeter", c.perimeter},
                          {"area_drift", c.area_drift},
                          {"max_strain", c.max_strain},
                          {"shape", {{"kind", c.shape.kind},
                                     {"rear_concavity", c.shape.rear_concavity},
                                     {"front_concavity", c.shape.front_concavity},
                                     {"side_concavity", c.shape.side_concavity},
                                     {"fore_aft", c.shape.fore_aft},
                                     {"length", c.shape.length},
                                     {"width", c.shape.width}}},
                          {"own_frame", {{"angle", c.own_frame.angle},
                                         {"top_dimple", c.own_frame.top_dimple},
                                         {"bottom_dimple", c.own_frame.bottom_dimple},
                                         {"end_concavity", c.own_frame.end_concavity},
                                         {"biconcave", c.own_frame.biconcave}}}});
  if (!sim.disks().empty()) j["disk_contact_steps"] = sim.contact_steps();
  if (scene.repulsion_strength > 0) j["membrane_repulsion_steps"] = sim.repulsion_steps();
  j["disks"] = nlohmann::json::array();
  for (const Disk& d : sim.disks())
    j["disks"].push_back({{"center", {d.center.x(), d.center.y()}},
                          {"radius", d.radius},
                          {"velocity", {d.velocity.x(), d.velocity.y()}},
                          {"angular_velocity", d.angular_velocity},
                          {"angle", d.angle}});
  if (const ObstacleConstraint* ob = sim.obstacles()) {
    const PartVelocities pv = part_velocities(ob->geometry(), flow.velocity());
    j["obstacles"] = {{"count", scene.obstacles.size()},
                      {"wide_velocity", pv.wide},
                      {"narrow_velocity", pv.narrow},
                      {"wide_flux", pv.wide_flux},
                      {"narrow_flux", pv.narrow_flux},
                      {"wide_height", pv.wide_height},
                      {"narrow_height", pv.narrow_height},
                      {"velocity_definition", "flux through each section over its open height, averaged over the part's sections, at the end"},
                      {"uzawa_preconditioner", scene.obstacle_preconditioner},
                      {"uzawa_solves", ob->solves()},
                      {"uzawa_iterations_mean", ob->solves() ? double(ob->total_iterations()) / double(ob->solves()) : 0.0},
                      {"uzawa_iterations_max", ob->max_iterations_seen()},
                      {"setup_seconds", ob->setup_seconds()}};
  }
  j["max_speed"] = s.max_speed;
  j["reynolds0"] = scene.reynolds0 ? nlohmann::json(*scene.reynolds0) : nlohmann::json(nullptr);
  j["body_force"] = scene.driving_force();
  j["mesh"] = {{"nx", flow.mesh().nx}, {"ny", flow.mesh().ny}, {"h", scene.mesh_size}};
  j["dt"] = scene.dt;
  j["coupling"] = scene.coupling;
  j["projection"] = scene.projection;
  j["scheme"] = scene.scheme;
  j["extrapolate_pressure"] = scene.extrapolate_pressure;
  if (!scene.disks.empty()) j["disk_boundary_spacing"] = scene.disk_boundary_spacing;
  if (coupling_by_gmres(scene)) {  // how GMRES solves and its tolerance: they change the bits
    j["coupling_options"] = describe(CouplingOptions{});
    j["coupling_tolerance"] = scene.coupling_tolerance;
  }
  if (!cells.empty())
    j["membrane"] = {{"units", scene.membrane_constants.units}, {"kl", sim.membrane().kl}, {"kb", sim.membrane().kb},
                     {"ks", sim.membrane().ks}, {"area_penalty", scene.area_penalty}, {"nodes", scene.membrane_nodes},
                     {"radius", scene.membrane_radius}};
  j["threads"] = omp_get_max_threads();
  j["scene"] = scene.source;
  j["version"] = RBCFLOW_VERSION;
  // What made it (io/provenance.hpp): the code and commit, the command, this invocation's start and
  // end (a resumed run: the last invocation's), the resolved scene beside it (scene.toml).
  j["code"] = code_id();
  j["commit"] = commit_id();
  j["command"] = command_line();
  j["started"] = started;
  j["ended"] = utc_now();
  j["instruction_set"] = RBCFLOW_INSTRUCTION_SET;  // results differ at round-off between sets (CMakeLists.txt)
  j["units"] = "SI: m, s, kg; velocities m/s, forces N/m^3, areas m^2, hematocrit %";
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  check_written(f.flush(), path);
}

}  // namespace

// A run in its phases: build the scene's parts, resume or start the outputs, step to the end
// (health checks, samples, checkpoints), then write the end's files.
RunSummary run_scene(const Scene& scene, const RunOptions& opt) {
  prepare_output_dir(opt.out_dir);
  omp_set_num_threads(opt.threads > 0 ? opt.threads : default_threads());
  const fs::path out(opt.out_dir);
  const FolderLock lock(out);
  if (!opt.resume) clear_other_run(out, opt.refuse_other_run);
  const std::string started = utc_now();
  // (Not over the scene file the run was read from, should it lie there under that name.)
  std::error_code same_ec;
  if (!opt.resume && !fs::equivalent(scene.source, out / "scene.toml", same_ec)) write_scene_file(out / "scene.toml", scene);

  Simulation sim(scene);
  if (!sim.cells().empty() && opt.progress) print_membrane_header(scene, sim.membrane());
  const long total = std::lround(std::ceil(scene.end / scene.dt - 1e-9));
  const long every = std::max(1L, std::lround(scene.sample_interval() / scene.dt));
  const RunState resumed = opt.resume ? resume_run(out, scene, sim, opt.progress, opt.any_code) : RunState{};
  RunOutputs outputs(out, scene, sim, resumed, !opt.resume);

  ProgressMeter progress(opt.label, total, total * scene.dt, opt.progress);
  progress.resumed_at(sim.steps());
  if (!opt.resume) {
    outputs.sample();
    outputs.snapshots_due();
    outputs.frames_due();
  }
  // Checkpoints: after a step that passed the health checks, with the outputs flushed.
  StopSignals signals;
  auto checkpoint = [&] { write_checkpoint(out, scene, sim, outputs.state(resumed.wall_seconds + progress.elapsed_seconds())); };
  double last_checkpoint_wall = 0;
  bool have_checkpoint = opt.resume;
  double checkpoint_time = sim.time();  // of the newest checkpoint (resume: the one read)
  try {
    while (sim.steps() < total) {
      const double t_before = sim.time();
      sim.step();
      sim.check_health();
      outputs.after_step();
      if (sim.steps() % every == 0 || sim.steps() == total) outputs.sample();
      outputs.snapshots_due();
      outputs.frames_due();
      progress.update(sim.steps(), sim.time());
      if (opt.after_step) opt.after_step(sim.steps());
      if (const int sig = g_stop_signal) {
        checkpoint();
        std::ostringstream m;
        m << "interrupted by " << signal_name(sig) << " at t = " << sim.time() << " s (step " << sim.steps()
          << "); checkpoint written to " << (out / "checkpoint.bin").string() << "; continue with: rbcflow resume " << opt.out_dir;
        throw RunInterrupted(m.str(), sig);
      }
      const double wall = progress.elapsed_seconds();
      const bool by_wall = opt.checkpoint_wall > 0 && wall - last_checkpoint_wall >= opt.checkpoint_wall;
      const bool by_sim = opt.checkpoint_sim > 0 &&
                          std::floor(sim.time() / opt.checkpoint_sim + 1e-9) > std::floor(t_before / opt.checkpoint_sim + 1e-9);
      if ((by_wall || by_sim) && sim.steps() < total) {
        checkpoint();
        last_checkpoint_wall = wall;
        have_checkpoint = true;
        checkpoint_time = sim.time();
      }
    }
  } catch (const RunFailure& e) {
    // The last checkpoint (if any) is the last good state: say where it is.
    if (!have_checkpoint) throw;
    std::ostringstream m;
    m << e.what() << "; the last good state (t = " << checkpoint_time << " s) is in " << (out / "checkpoint.bin").string();
    throw RunFailure(m.str());
  }
  progress.finish(sim.steps(), sim.time());

  RunSummary s;
  s.steps = sim.steps();
  s.t_end = sim.time();
  s.wall_seconds = resumed.wall_seconds + progress.elapsed_seconds();
  s.mean_velocity = outputs.last_mean();
  s.nodal_mean_velocity = outputs.last_nodal();
  s.reynolds = reynolds_number(s.mean_velocity, scene.fluid, scene.height);
  s.max_speed = max_speed(sim.flow().velocity());
  s.hematocrit = hematocrit_percent(sim.cells(), scene.fluid_area());
  for (const Cell& c : sim.cells()) s.cells.push_back(measure_cell(c, sim.membrane().rest_length()));
  write_profile(out / "profile.csv", sim.flow());
  if (!sim.cells().empty()) {
    std::ofstream fin(out / "membranes_final.dat");
    write_membranes(fin, sim.cells(), sim.time());
  }
  write_summary(out / "summary.json", scene, sim, s, started);
  return s;
}

std::optional<RunSummary> read_finished_run(const std::string& dir, const Scene& scene, bool any_code) {
  const fs::path path = fs::path(dir) / "summary.json";
  if (!fs::exists(path)) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
    if (!any_code && j.value("code", std::string()) != code_id()) return std::nullopt;  // other code: run again
    // (A summary without "projection" is older than the incremental form's key: the study's form;
    // one without "scheme" older than the extrapolated scheme: the study's Lie scheme; without
    // "extrapolate_pressure" or "disk_boundary_spacing", older than those keys: their defaults.)
    if (j.at("scene") != scene.source || j.at("dt") != scene.dt || j.at("coupling") != scene.coupling ||
        j.value("projection", std::string("study")) != scene.projection || j.value("scheme", std::string("lie")) != scene.scheme ||
        j.value("extrapolate_pressure", true) != scene.extrapolate_pressure ||
        (!scene.disks.empty() && j.value("disk_boundary_spacing", 1.0) != scene.disk_boundary_spacing) ||
        std::abs(j.at("t_end").get<double>() - scene.end) > scene.dt)  // the run ends at the first step at or past end
      return std::nullopt;
    // How the coupling's GMRES solves and where it stops change the run like a start perturbation
    // (a summary without "coupling_options" was written by a version whose solve could differ).
    if (coupling_by_gmres(scene) && (j.value("coupling_options", std::string()) != describe(CouplingOptions{}) ||
                                     j.value("coupling_tolerance", 1e-4) != scene.coupling_tolerance))
      return std::nullopt;
    RunSummary s;
    s.steps = j.at("steps");
    s.t_end = j.at("t_end");
    s.wall_seconds = j.at("wall_seconds");
    s.mean_velocity = j.at("mean_velocity");
    s.reynolds = j.at("reynolds");
    s.nodal_mean_velocity = j.value("nodal_mean_velocity", std::numeric_limits<double>::quiet_NaN());  // absent before format 5
    s.hematocrit = j.at("hematocrit");
    s.max_speed = j.at("max_speed");
    for (const auto& c : j.at("cells")) {
      CellState cs;
      cs.centroid = Eigen::Vector2d(c.at("centroid")[0].get<double>(), c.at("centroid")[1].get<double>());
      cs.area = c.at("area");
      cs.perimeter = c.at("perimeter");
      cs.area_drift = c.at("area_drift");
      cs.max_strain = c.at("max_strain");
      const auto& sh = c.at("shape");
      cs.shape.kind = sh.at("kind");
      cs.shape.rear_concavity = sh.at("rear_concavity");
      cs.shape.front_concavity = sh.at("front_concavity");
      cs.shape.side_concavity = sh.at("side_concavity");
      cs.shape.fore_aft = sh.at("fore_aft");
      cs.shape.length = sh.at("length");
      cs.shape.width = sh.at("width");
      const auto& of = c.at("own_frame");
      cs.own_frame.angle = of.at("angle");
      cs.own_frame.top_dimple = of.at("top_dimple");
      cs.own_frame.bottom_dimple = of.at("bottom_dimple");
      cs.own_frame.end_concavity = of.at("end_concavity");
      cs.own_frame.biconcave = of.at("biconcave");
      s.cells.push_back(cs);
    }
    return s;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable or from another version: run again
  }
}

}  // namespace rbc
