#include "io/checkpoint.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fcntl.h>
#include <unistd.h>

namespace rbc {

namespace {
const char kMagic[] = "RBCFLOW-CHECKPOINT";  // 18 bytes, no terminator in the file
constexpr std::size_t kMagicSize = sizeof(kMagic) - 1;
constexpr std::size_t kHeader = kMagicSize + sizeof(std::uint32_t);
}  // namespace

std::uint64_t fnv1a64(const unsigned char* p, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

void CheckpointWriter::raw(const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  bytes_.insert(bytes_.end(), b, b + n);
}

void CheckpointWriter::put(const std::string& s) {
  put(std::int64_t(s.size()));
  raw(s.data(), s.size());
}

void CheckpointWriter::put(const std::vector<double>& v) {
  put(std::int64_t(v.size()));
  raw(v.data(), v.size() * sizeof(double));
}

void CheckpointWriter::put(const Eigen::VectorXd& v) {
  put(std::int64_t(v.size()));
  raw(v.data(), std::size_t(v.size()) * sizeof(double));
}

void CheckpointWriter::put(const std::vector<Eigen::Vector2d>& points) {
  put(std::int64_t(2 * points.size()));
  for (const Eigen::Vector2d& p : points) raw(p.data(), 2 * sizeof(double));
}

void CheckpointWriter::commit(const std::string& path) const {
  namespace fs = std::filesystem;
  std::vector<unsigned char> file(kMagic, kMagic + kMagicSize);
  const std::uint32_t format = kCheckpointFormat;
  const auto* f = reinterpret_cast<const unsigned char*>(&format);
  file.insert(file.end(), f, f + sizeof format);
  file.insert(file.end(), bytes_.begin(), bytes_.end());
  const std::uint64_t sum = fnv1a64(file.data(), file.size());
  const auto* s = reinterpret_cast<const unsigned char*>(&sum);
  file.insert(file.end(), s, s + sizeof sum);
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write_synced(tmp, file.data(), file.size());
  } catch (const CheckpointError&) {
    std::error_code ignored;
    fs::remove(tmp, ignored);  // the last good checkpoint stays as it was
    throw;
  }
  std::error_code ec;
  if (fs::exists(path)) {
    // NAME.prev from a hard link of NAME (renamed over the old .prev), NAME itself untouched.
    const std::string link = path + ".prev.tmp." + std::to_string(::getpid());
    std::error_code ignored;
    fs::remove(link, ignored);
    fs::create_hard_link(path, link, ec);
    if (ec) fs::copy_file(path, link, fs::copy_options::overwrite_existing, ec);  // (a file system without hard links)
    if (!ec) fs::rename(link, path + ".prev", ec);
    if (ec) {
      fs::remove(tmp, ignored);
      throw CheckpointError(path + ": cannot keep the previous checkpoint (" + ec.message() + ")");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw CheckpointError(path + ": cannot rename the new checkpoint into place (" + ec.message() + ")");
  }
  sync_folder(fs::path(path).parent_path().string());
}

void write_synced(const std::string& path, const void* data, std::size_t n) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError(path + ": cannot create (" + std::strerror(errno) + ")");
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t done = 0;
  while (done < n) {
    const ::ssize_t w = ::write(fd, p + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      throw CheckpointError(path + ": cannot write (" + why + "; disk full or folder not writable?)");
    }
    done += std::size_t(w);
  }
  const bool synced = ::fsync(fd) == 0;
  const std::string why = synced ? "" : std::strerror(errno);
  if (::close(fd) != 0 || !synced) throw CheckpointError(path + ": cannot sync to the disk (" + (synced ? std::strerror(errno) : why) + ")");
}

bool sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0;
  const int err = errno;
  ::close(fd);
  errno = err;
  return synced;
}

void sync_folder(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // (a folder that cannot be opened for reading: its renames stand unsynced)
  ::fsync(fd);
  ::close(fd);
}

CheckpointReader::CheckpointReader(const std::string& path) : path_(path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path + ": cannot open the checkpoint");
  bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (bytes_.size() < kHeader + sizeof(std::uint64_t) || std::memcmp(bytes_.data(), kMagic, kMagicSize) != 0)
    throw CheckpointError(path + ": not an rbcflow checkpoint");
  std::uint32_t format = 0;
  std::memcpy(&format, bytes_.data() + kMagicSize, sizeof format);
  if (format != kCheckpointFormat)
    throw CheckpointError(path + ": checkpoint format " + std::to_string(format) + ", this rbcflow reads format " +
                          std::to_string(kCheckpointFormat));
  end_ = bytes_.size() - sizeof(std::uint64_t);
  std::uint64_t sum = 0;
  std::memcpy(&sum, bytes_.data() + end_, sizeof sum);
  if (sum != fnv1a64(bytes_.data(), end_)) throw CheckpointError(path + ": checksum mismatch (a damaged or truncated checkpoint)");
  pos_ = kHeader;
}

void CheckpointReader::raw(void* p, std::size_t n) {
  if (n > end_ - pos_) throw CheckpointError(path_ + ": ends too early (written by another version?)");
  if (n == 0) return;  // (an empty record: its vector's data() may be null, which memcpy must not get)
  std::memcpy(p, bytes_.data() + pos_, n);
  pos_ += n;
}

double CheckpointReader::get_double() {
  double v;
  raw(&v, sizeof v);
  return v;
}

std::int64_t CheckpointReader::get_int() {
  std::int64_t v;
  raw(&v, sizeof v);
  return v;
}

std::string CheckpointReader::get_string() {
  const std::int64_t n = get_int();
  if (n < 0 || std::size_t(n) > end_ - pos_) throw CheckpointError(path_ + ": a text record has an impossible length");
  std::string s(static_cast<std::size_t>(n), '\0');
  raw(s.data(), s.size());
  return s;
}

std::vector<double> CheckpointReader::get_doubles() {
  const std::int64_t n = get_int();
  if (n < 0 || std::size_t(n) > (end_ - pos_) / sizeof(double))
    throw CheckpointError(path_ + ": a field record has an impossible length");
  std::vector<double> v(static_cast<std::size_t>(n));
  raw(v.data(), v.size() * sizeof(double));
  return v;
}

std::vector<double> CheckpointReader::get_doubles(std::size_t n, const char* what) {
  std::vector<double> v = get_doubles();
  if (v.size() != n)
    throw CheckpointError(path_ + ": " + what + " has " + std::to_string(v.size()) + " values, this scene needs " +
                          std::to_string(n));
  return v;
}

Eigen::VectorXd CheckpointReader::get_vector() {
  const std::vector<double> v = get_doubles();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

std::vector<Eigen::Vector2d> CheckpointReader::get_points(std::size_t n, const char* what) {
  const std::vector<double> v = get_doubles(2 * n, what);
  std::vector<Eigen::Vector2d> points(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = Eigen::Vector2d(v[2 * i], v[2 * i + 1]);
  return points;
}

}  // namespace rbc
