/// Where tools read and write: files, or '-' for standard input and output.
///
/// Output is atomic: it is written to a temporary file beside the target
/// (`.NAME.tmp-XXXXXX`) and renamed onto it only by commit(); a failure or an
/// interrupt removes the temporary, so a failed run leaves no partial file and never
/// overwrites a good one. An existing target is refused unless --force.
/// HDF5 on standard output is written as an in-memory file image (HDF5's core driver
/// and H5Fget_file_image); reading '-' reads standard input to the end and opens the
/// bytes as a file image. See docs/cli.md, "Pipes".
#pragma once

#include "cdpile/io/h5.hpp"

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace cdpile::io {

/// The reader of standard output closed it (EPIPE) before everything was written: not an
/// error of the tool, which ends as if killed by SIGPIPE (docs/cli.md, "Pipes and HDF5").
class BrokenPipe : public Error {
 public:
  BrokenPipe() : Error("stdout", "", "broken pipe") {}
};

/// The 8-byte signature at the start of an HDF5 file (no user block).
bool has_hdf5_signature(const std::vector<char>& bytes);
bool has_hdf5_signature(const std::string& path);

/// Reads a whole input ('-' = standard input) into memory. Error if empty stdin.
std::vector<char> read_all(const std::string& path);

/// A readable input: an HDF5 file (from a path or from bytes on stdin) or a text table.
class Input {
 public:
  /// Opens `path` ('-' = stdin). HDF5 is recognised by its signature, whatever the name.
  explicit Input(const std::string& path);
  bool is_hdf5() const { return file_.valid(); }
  /// The open HDF5 file; error naming the file if the input is not HDF5.
  const h5::File& hdf5() const;
  /// The text of a non-HDF5 input.
  const std::string& text() const { return text_; }
  /// The name used in messages ("stdin" for '-').
  const std::string& name() const { return name_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_, name_, text_;
  std::vector<char> image_;  // keeps a stdin image alive while the file is open
  h5::File file_;
};

/// An output target, committed atomically (see the file comment).
class Output {
 public:
  /// `path` '-' = standard output. Refuses an existing file unless `force`, and a
  /// directory; with `binary` (the output will be HDF5) also a terminal as standard output,
  /// here, so that a tool refuses before its work (create_hdf5 checks again).
  Output(std::string path, bool force, bool binary = false);
  ~Output();
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;

  bool is_stdout() const { return path_ == "-"; }
  const std::string& path() const { return path_; }
  /// The name used in messages ("stdout" for '-').
  const std::string& name() const { return name_; }

  /// Creates the HDF5 file to write into (temporary file, or in memory for stdout).
  h5::File& create_hdf5();
  /// A text stream to write a table into (temporary file, or a buffer for stdout).
  std::ostream& text();

  /// Finishes: closes the file and renames it onto the target, or writes the image or
  /// the text to stdout. Errors (disk full, broken pipe) throw and remove the temporary.
  void commit();
  bool committed() const { return committed_; }

  /// The path of the temporary file being written (empty for stdout).
  const std::string& temporary_path() const { return tmp_; }

 private:
  std::string path_, name_, tmp_;
  bool committed_ = false;
  h5::File file_;
  std::unique_ptr<std::ofstream> fstream_;
  std::unique_ptr<std::ostringstream> sstream_;
  void discard() noexcept;
};

/// Registers a temporary file to be removed if the process is interrupted.
void register_temporary(const std::string& path);
void unregister_temporary(const std::string& path);
/// Removes all registered temporaries (async-signal-safe: unlink only).
void remove_temporaries() noexcept;

/// Atomic replacement of `target` by `source` (rename within a folder).
void rename_onto(const std::string& source, const std::string& target);

/// A unique temporary path beside `target`: DIR/.NAME.tmp-XXXXXX (file created, empty);
/// NAME is cut to fit the file system's limit on a name (NAME_MAX, 255 bytes), so that
/// every legal output name has a temporary.
std::string make_temporary_beside(const std::string& target);
/// The fixed part of make_temporary_beside's names for `target`: DIR/.NAME.tmp-
std::string temporary_prefix(const std::string& target);

}  // namespace cdpile::io
