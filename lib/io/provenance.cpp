#include "io/provenance.hpp"

#include <ctime>

#include "rbcflow_code_id.hpp"  // generated at build time (cmake/code_id.cmake)

namespace rbc {

const char* code_id() { return RBCFLOW_CODE_ID; }
const char* commit_id() { return RBCFLOW_COMMIT; }

std::string version_line(const std::string& program) {
  return (program == "rbcflow" ? program : "rbcflow " + program) + ": code " + code_id() + ", commit " + commit_id();
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

namespace {
std::string& the_command_line() {
  static std::string c;
  return c;
}
}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string c;
  for (int k = 0; k < argc; ++k) {
    const std::string w = argv[k];
    c += (k ? " " : "") + (w.find(' ') == std::string::npos ? w : "'" + w + "'");
  }
  the_command_line() = c;
}

const std::string& command_line() { return the_command_line(); }

}  // namespace rbc
