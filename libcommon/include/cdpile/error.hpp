/// The two kinds of failure a tool reports, and how they read.
///
/// Every message is one line, `FILE: WHERE: WHAT` (WHERE is a path inside an HDF5 file,
/// a line and column of a table, or empty), printed by the CLI layer as
/// `tool: FILE: WHERE: WHAT`. Exit codes: 1 for a runtime or data error, 2 for a usage
/// error (docs/cli.md).
#pragma once

#include <cstdint>
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

/// `text` made safe to print on a terminal: control bytes (C0 but the tab, DEL, the C1 controls
/// U+0080..U+009F) and bytes that are not valid UTF-8 are written as `\xNN`, so that a
/// name or a string read from a damaged file can neither move the cursor nor switch the
/// terminal's mode. Every message a tool prints passes
/// through it (cli::run_tool, cli::warn, cli::info).
inline std::string printable(const std::string& text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  auto escape = [&](unsigned char c) {
    out += "\\x";
    out += hex[c >> 4];
    out += hex[c & 15];
  };
  const std::size_t n = text.size();
  for (std::size_t k = 0; k < n;) {
    const auto c = static_cast<unsigned char>(text[k]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) {
      escape(c);
      ++k;
      continue;
    }
    if (c < 0x80) {
      out += static_cast<char>(c);
      ++k;
      continue;
    }
    // A multi-byte UTF-8 sequence: its length from the lead byte, its continuation bytes
    // 10xxxxxx, no overlong form, no surrogate, at most U+10FFFF, and not a C1 control.
    std::size_t len = c >= 0xc2 && c <= 0xdf   ? 2
                      : c >= 0xe0 && c <= 0xef ? 3
                      : c >= 0xf0 && c <= 0xf4 ? 4
                                               : 0;
    bool ok = len > 0 && k + len <= n;
    std::uint32_t cp = len == 2 ? c & 0x1fu : len == 3 ? c & 0x0fu : c & 0x07u;
    for (std::size_t q = 1; ok && q < len; ++q) {
      const auto d = static_cast<unsigned char>(text[k + q]);
      ok = (d & 0xc0) == 0x80;
      cp = (cp << 6) | (d & 0x3fu);
    }
    if (ok)
      ok = !(len == 3 && (cp < 0x800 || (cp >= 0xd800 && cp <= 0xdfff))) &&
           !(len == 4 && (cp < 0x10000 || cp > 0x10ffff)) && !(cp >= 0x80 && cp <= 0x9f);
    if (!ok) {
      escape(c);
      ++k;
      continue;
    }
    out.append(text, k, len);
    k += len;
  }
  return out;
}

/// The command line is wrong: unknown option, bad value, missing argument. Exit code 2.
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace cdpile
