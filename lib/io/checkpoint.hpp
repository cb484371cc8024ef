#pragma once
// Checkpoint files: everything the next step needs, in one binary file per run folder.
//
//   layout   "RBCFLOW-CHECKPOINT" magic, format number (uint32), then the payload (records
//            written by the parts of the run, in order), then the FNV-1a 64-bit checksum of
//            everything before it.
//   writing  to NAME.tmp.<pid> (a second process never shares it), written, checked and synced
//            to the disk (fsync); the previous NAME becomes NAME.prev through a hard link
//            renamed over NAME.prev, so that NAME exists at every instant; then NAME.tmp.<pid>
//            is renamed over NAME and the folder synced. A crash at any point leaves NAME whole
//            (the old or the new one) and the previous checkpoint until the new one is on disk.
//   reading  the whole file, magic, format and checksum checked before any value is used; every
//            read is bounds-checked. Any problem is a CheckpointError naming the file and what
//            is wrong.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rbc {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// 2: the semi-implicit coupling also keeps the right-hand sides of its last two steps.
// 3: the simulation also keeps the time its fluid has spent above the speed limit (check_health).
// 4: same payload; series.csv with cells has two more columns (the plasma alone) and the s* = 1
//    cell is the regular polygon at rest, so a run of format 3 cannot be continued by this one.
// 5: the run's state also keeps the nodal mean U_n's average in progress (series.csv's
//    nodal_mean_velocity column).
inline constexpr std::uint32_t kCheckpointFormat = 5;

class CheckpointWriter {
 public:
  void put(double v) { raw(&v, sizeof v); }
  void put(std::int64_t v) { raw(&v, sizeof v); }
  void put(const std::string& s);
  void put(const std::vector<double>& v);
  void put(const Eigen::VectorXd& v);
  void put(const std::vector<Eigen::Vector2d>& points);  // membrane nodes (x, y pairs)
  void put_raw(const void* p, std::size_t n) { raw(p, n); }  // bytes as they are (the fuzzer's payloads)
  // Writes the file as described above; throws CheckpointError if it cannot.
  void commit(const std::string& path) const;

 private:
  void raw(const void* p, std::size_t n);
  std::vector<unsigned char> bytes_;
};

// Writes n bytes to path and syncs them to the disk (open, write, fsync, close), or throws
// CheckpointError naming the file and the system's reason (the caller removes what it made).
void write_synced(const std::string& path, const void* data, std::size_t n);
// Syncs a file's data written so far through any stream to the disk (open, fsync, close); false
// with errno set where it cannot.
bool sync_file(const std::string& path);
// Syncs a folder's entries (its renames) to the disk; silently nothing where it cannot be opened.
void sync_folder(const std::string& dir);

class CheckpointReader {
 public:
  explicit CheckpointReader(const std::string& path);  // reads and checks the whole file
  double get_double();
  std::int64_t get_int();
  std::string get_string();
  std::vector<double> get_doubles();
  // A vector that must have exactly n values (a field of this mesh, the nodes of this cell).
  std::vector<double> get_doubles(std::size_t n, const char* what);
  Eigen::VectorXd get_vector();
  std::vector<Eigen::Vector2d> get_points(std::size_t n, const char* what);  // exactly n nodes
  const std::string& path() const { return path_; }
  bool at_end() const { return pos_ == end_; }

 private:
  void raw(void* p, std::size_t n);
  std::string path_;
  std::vector<unsigned char> bytes_;
  std::size_t pos_ = 0, end_ = 0;  // payload range
};

std::uint64_t fnv1a64(const unsigned char* p, std::size_t n);

}  // namespace rbc
