#pragma once
// What made a result: the code id (cmake/code_id.sh: the hash of the sources that make the
// numbers, with a suffix for uncommitted changes), the commit, and the instant, for every output
// folder (summary.json), checkpoint and program (--version).
#include <string>

namespace rbc {

// The code id and commit of this build ("unknown" outside a git checkout).
const char* code_id();
const char* commit_id();
// "rbcflow <program>: code <code id>, commit <commit>" (every program's --version).
std::string version_line(const std::string& program);
// The current instant, UTC, ISO 8601 ("2026-11-29T09:30:00Z").
std::string utc_now();
// The program's command line, as its main was given it (every main sets it first; summary.json
// records it): the words joined by spaces, quoted where they hold a space.
void set_command_line(int argc, const char* const* argv);
const std::string& command_line();

}  // namespace rbc
