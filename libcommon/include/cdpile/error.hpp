/// The two kinds of failure a tool reports, and how they read.
///
/// Every message is one line, `FILE: WHERE: WHAT` (WHERE is a path inside an HDF5 file,
/// a line and column of a table, or empty), printed by the CLI layer as
/// `tool: FILE: WHERE: WHAT`. Exit codes: 1 for a runtime or data error, 2 for a usage
/// error (docs/cli.md).
#pragma once

#include <stdexcept>
#include <string>

namespace cdpile {

/// A runtime or data error: bad or unreadable input, a failed write. Exit code 1.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
  /// `file: where: what`, leaving out empty parts.
  Error(const std::string& file, const std::string& where, const std::string& what)
      : std::runtime_error(join(file, where, what)) {}

  static std::string join(const std::string& file, const std::string& where,
                          const std::string& what) {
    std::string s;
    if (!file.empty()) s += file + ": ";
    if (!where.empty()) s += where + ": ";
    return s + what;
  }
};

/// The command line is wrong: unknown option, bad value, missing argument. Exit code 2.
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace cdpile
