#include "cdpile/io/files.hpp"

#include "cdpile/fields.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>

namespace cdpile::io {

namespace {

constexpr std::array<unsigned char, 8> kHdf5Signature = {0x89, 'H',  'D',  'F',
                                                         '\r', '\n', 0x1a, '\n'};

// Temporaries to remove on an interrupt. A fixed table of C strings, so the signal
// handler can walk it with nothing but unlink().
constexpr std::size_t kMaxTemporaries = 64;
constexpr std::size_t kMaxPath = 4096;
char g_temporaries[kMaxTemporaries][kMaxPath];
std::atomic<bool> g_used[kMaxTemporaries];
std::mutex g_temporaries_mutex;

std::string system_reason() { return std::strerror(errno); }

void write_fully(int fd, const char* data, std::size_t n, const std::string& name) {
  while (n > 0) {
    ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      if (errno == EPIPE) throw BrokenPipe();
      throw Error(name, "", "write failed: " + system_reason());
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
}

}  // namespace

bool has_hdf5_signature(const std::vector<char>& bytes) {
  return bytes.size() >= 8 && std::equal(kHdf5Signature.begin(), kHdf5Signature.end(),
                                         reinterpret_cast<const unsigned char*>(bytes.data()));
}

bool has_hdf5_signature(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> head(8);
  if (!in.read(head.data(), 8)) return false;
  return has_hdf5_signature(head);
}

std::vector<char> read_all(const std::string& path) {
  std::vector<char> bytes;
  if (path == "-") {
    std::array<char, 1 << 16> buf;
    while (true) {
      ssize_t r = ::read(STDIN_FILENO, buf.data(), buf.size());
      if (r < 0) {
        if (errno == EINTR) continue;
        throw Error("stdin", "", "read failed: " + system_reason());
      }
      if (r == 0) break;
      bytes.insert(bytes.end(), buf.data(), buf.data() + r);
    }
    if (bytes.empty())
      throw Error("stdin", "", "no data on standard input (did the previous tool fail?)");
    return bytes;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path, "", "is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot open: " + system_reason());
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return bytes;
}

Input::Input(const std::string& path) : path_(path), name_(path == "-" ? "stdin" : path) {
  if (path == "-") {
    if (isatty(STDIN_FILENO))
      throw Error("stdin", "", "standard input is a terminal; pipe data in or give a file");
  } else {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path, "", "no such file");
    if (std::filesystem::is_directory(path, ec)) throw Error(path, "", "is a directory");
    if (std::filesystem::is_regular_file(path, ec)) {
      if (has_hdf5_signature(path)) {
        file_ = h5::open_read(path, name_);
      } else {
        auto bytes = read_all(path);
        text_.assign(bytes.begin(), bytes.end());
      }
      return;
    }
  }
  // Standard input, a FIFO, a process substitution (<(tool -o -)) or a device: it can be
  // read once, from the start, so it is read whole and opened from memory.
  image_ = read_all(path);
  if (path != "-" && image_.empty())
    throw Error(path, "", "no data (did the tool writing it fail?)");
  if (has_hdf5_signature(image_)) {
    file_ = h5::open_image(image_, name_);
  } else {
    text_.assign(image_.begin(), image_.end());
    image_.clear();
  }
}

const h5::File& Input::hdf5() const {
  if (!file_.valid()) throw Error(name_, "", "not an HDF5 file (no HDF5 signature)");
  return file_;
}

void register_temporary(const std::string& path) {
  std::lock_guard lock(g_temporaries_mutex);
  for (std::size_t k = 0; k < kMaxTemporaries; ++k) {
    if (!g_used[k].load()) {
      std::snprintf(g_temporaries[k], kMaxPath, "%s", path.c_str());
      g_used[k].store(true);
      return;
    }
  }
}

void unregister_temporary(const std::string& path) {
  std::lock_guard lock(g_temporaries_mutex);
  for (std::size_t k = 0; k < kMaxTemporaries; ++k)
    if (g_used[k].load() && path == g_temporaries[k]) g_used[k].store(false);
}

void remove_temporaries() noexcept {
  for (std::size_t k = 0; k < kMaxTemporaries; ++k)
    if (g_used[k].load()) ::unlink(g_temporaries[k]);
}

void rename_onto(const std::string& source, const std::string& target) {
  if (std::rename(source.c_str(), target.c_str()) != 0)
    throw Error(target, "", "cannot rename the finished output into place: " + system_reason());
}

std::string temporary_prefix(const std::string& target) {
  std::filesystem::path t(target);
  std::filesystem::path dir = t.has_parent_path() ? t.parent_path() : std::filesystem::path(".");
  // "." + NAME + ".tmp-XXXXXX" is 12 bytes longer than NAME: a legal output name of more
  // than NAME_MAX - 12 bytes (255 on Linux) would have no legal temporary, so its name is
  // cut; mkstemp's six random characters keep it unique.
  const long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  const std::size_t room = static_cast<std::size_t>(name_max > 0 ? name_max : 255) - 12;
  std::string name = t.filename().string();
  if (name.size() > room) name.resize(room);
  return (dir / ("." + name + ".tmp-")).string();
}

std::string make_temporary_beside(const std::string& target) {
  std::string pattern = temporary_prefix(target) + "XXXXXX";
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  int fd = mkstemp(buf.data());
  if (fd < 0)
    throw Error(target, "", "cannot create a temporary file beside it: " + system_reason());
  // mkstemp makes the file 0600; the finished output gets the usual 0666 & ~umask.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  std::string path(buf.data());
  register_temporary(path);
  return path;
}

namespace {
[[noreturn]] void refuse_terminal() {
  throw Error("stdout", "", "refusing to write HDF5 to a terminal (use -o FILE or a pipe)");
}
}  // namespace

Output::Output(std::string path, bool force, bool binary)
    : path_(std::move(path)), name_(path_ == "-" ? "stdout" : path_) {
  if (path_.empty())
    throw UsageError("no output file given (-o FILE, or -o - for standard output)");
  if (is_stdout()) {
    if (binary && isatty(STDOUT_FILENO)) refuse_terminal();
    return;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) throw Error(path_, "", "output is a directory");
  if (std::filesystem::exists(path_, ec) && !force)
    throw Error(path_, "", "exists; not overwritten (use " + field("force") + " to replace it)");
  std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw Error(path_, "", "folder " + parent.string() + " does not exist");
}

Output::~Output() {
  if (!committed_) discard();
}

void Output::discard() noexcept {
  if (file_.valid()) {
    try {
      file_ = h5::File();
    } catch (...) {
    }
  }
  fstream_.reset();
  if (!tmp_.empty()) {
    ::unlink(tmp_.c_str());
    unregister_temporary(tmp_);
    tmp_.clear();
  }
}

h5::File& Output::create_hdf5() {
  if (is_stdout()) {
    if (isatty(STDOUT_FILENO)) refuse_terminal();
    file_ = h5::create_in_memory(name_);
  } else {
    tmp_ = make_temporary_beside(path_);
    file_ = h5::create(tmp_, name_);
  }
  return file_;
}

std::ostream& Output::text() {
  if (is_stdout()) {
    sstream_ = std::make_unique<std::ostringstream>();
    return *sstream_;
  }
  tmp_ = make_temporary_beside(path_);
  fstream_ = std::make_unique<std::ofstream>(tmp_, std::ios::binary | std::ios::trunc);
  if (!*fstream_) throw Error(path_, "", "cannot write: " + system_reason());
  return *fstream_;
}

void Output::commit() {
  try {
    if (file_.valid()) {
      if (is_stdout()) {
        std::vector<char> img = h5::image_of(file_);
        file_ = h5::File();
        write_fully(STDOUT_FILENO, img.data(), img.size(), name_);
      } else {
        file_.close();
      }
    } else if (sstream_) {
      std::cout.flush();
      const std::string s = sstream_->str();
      write_fully(STDOUT_FILENO, s.data(), s.size(), name_);
    } else if (fstream_) {
      fstream_->flush();
      if (!*fstream_) throw Error(path_, "", "write failed (disk full?)");
      fstream_->close();
    }
    if (!tmp_.empty()) {
      rename_onto(tmp_, path_);
      unregister_temporary(tmp_);
      tmp_.clear();
    }
    committed_ = true;
  } catch (...) {
    discard();
    throw;
  }
}

}  // namespace cdpile::io
