// Files of HDF5's earlier format (superblock version 0 or 1: what cdpile wrote before it
// asked for the 1.10 format, and what most other programs still write by default).
//
// Nothing in that format is checksummed, and libhdf5 1.10.8 follows a damaged header,
// heap or B-tree wherever it points: the fuzzer made it crash (SIGSEGV, SIGBUS, SIGFPE,
// heap-corruption aborts) or loop for ever inside single library calls, before any
// check of cdpile's could run (docs/fuzzing.md, "Findings"). No check outside the
// library can see such damage coming, but a process can survive it in another process:
// such a file is first read whole in a forked child, bounded in CPU time and memory, the
// way the readers read it (read_every_object); only if the child comes back is the file
// read in this process. Its reads are a subset of the child's, made by the same library
// on the same bytes, so where the child did not crash they do not either.
//
// Refusing the earlier format outright would be simpler, but every run and product
// made before this version is in it, and nearly all of them are intact: the check keeps
// them readable for the price of reading each one twice (docs/cli.md, "What is refused").
#include "cdpile/io/h5.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#if defined(__SANITIZE_ADDRESS__)
#define CDPILE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CDPILE_ADDRESS_SANITIZER 1
#endif
#endif

// Set by libFuzzer (and callable by anyone) to run when a sanitizer reports an error: in
// the checking child it would save the input as a crash of the harness, though the
// crash is the expected outcome there and the parent handles it. Weak: absent without
// sanitizers.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace cdpile::io::h5 {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// The superblock version after the first signature in `read(offset, 9 bytes)`, searched
/// where HDF5 searches: offset 0, then 512, 1024, 2048, ... below the end of the file.
template <class Read>
int version_at_signature(std::uint64_t size, Read&& read) {
  unsigned char head[9];
  for (std::uint64_t at = 0; at + sizeof head <= size; at = at == 0 ? 512 : 2 * at) {
    if (!read(at, head)) return -1;
    if (std::equal(kSignature, kSignature + 8, head)) return head[8];
  }
  return -1;
}

/// Largest dataset read in one piece by read_every_object; larger ones in blocks of rows,
/// so that the child's memory does not grow with the file.
constexpr double kBlockElements = 1 << 22;

template <class T>
void read_in_blocks(const File& f, const std::string& path, const std::vector<hsize_t>& dims) {
  double elements = 1;
  for (hsize_t d : dims) elements *= static_cast<double>(d);
  if (dims.empty() || elements <= kBlockElements) {
    read<T>(f, path, {});
    return;
  }
  const double per_row = elements / static_cast<double>(dims[0]);
  const auto block = static_cast<hsize_t>(std::max(1.0, std::floor(kBlockElements / std::max(per_row, 1.0))));
  for (hsize_t first = 0; first < dims[0]; first += block) {
    try {
      read_rows<T>(f, path, first, std::min(block, dims[0] - first));
    } catch (const Error&) {  // a non-finite value in this block: the next blocks are still read
    }
  }
}

void read_dataset(const File& f, const std::string& path) {
  const std::vector<hsize_t> dims = shape(f, path);
  H5T_class_t cls = H5T_NO_CLASS;
  {
    Handle d(H5Dopen2(f.id(), path.c_str(), H5P_DEFAULT));
    Handle t(d.valid() ? H5Dget_type(d.id()) : H5I_INVALID_HID);
    if (t.valid()) cls = H5Tget_class(t.id());
  }
  if (cls != H5T_INTEGER) {
    read_in_blocks<double>(f, path, dims);  // numbers; anything else fails as in the readers
    return;
  }
  read_in_blocks<std::int64_t>(f, path, dims);
  // The readers also convert integers to these types: one row each takes HDF5 through
  // each conversion of this dataset's type.
  const hsize_t rows = dims.empty() || dims[0] == 0 ? 0 : 1;
  auto one_row = [&](auto tag) {
    try {
      read_rows<decltype(tag)>(f, path, 0, rows);
    } catch (const Error&) {
    }
  };
  if (rows > 0) {
    one_row(std::int32_t{});
    one_row(std::int8_t{});
    one_row(std::uint8_t{});
    one_row(double{});
  }
}

void read_attributes(const File& f, const std::string& path) {
  has_attr(f, path, "\x01 cdpile: absent");  // H5Aexists of an absent name reads every attribute message
  for (const std::string& name : attr_names(f, path)) {
    try {
      has_attr(f, path, name);
      switch (attr_class(f, path, name)) {
        case H5T_STRING: attr_strings(f, path, name); break;
        case H5T_INTEGER:
          try {
            attr_ints(f, path, name);
          } catch (const Error&) {
          }
          attr_double(f, path, name);
          break;
        default: attr_double(f, path, name);  // numbers; anything else fails as in the readers
      }
    } catch (const Error&) {
    }
  }
}

std::string child_path(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

/// In the child, before the file is read: no signal handler of the tool's (SIGINT's would
/// remove the parent's temporaries) or of a sanitizer's runs, no core file is written,
/// nothing is printed, and the bounds are set. The child dies with its parent.
void prepare_child(pid_t parent, double cpu_seconds, double memory_bytes) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGINT, SIGTERM, SIGXCPU, SIGPIPE})
    std::signal(sig, SIG_DFL);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
  const int null = ::open("/dev/null", O_WRONLY);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
  }
  const rlimit core{0, 0};
  ::setrlimit(RLIMIT_CORE, &core);
  const auto cpu = static_cast<rlim_t>(std::ceil(cpu_seconds));
  const rlimit cpu_limit{cpu, cpu + 1};  // SIGXCPU at the soft limit, SIGKILL a second later
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
#ifndef CDPILE_ADDRESS_SANITIZER
  // Above what is mapped now (the parent's data, an image from standard input).
  double mapped = 0;
  if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
    unsigned long pages = 0;
    if (std::fscanf(statm, "%lu", &pages) == 1) mapped = static_cast<double>(pages) * static_cast<double>(::sysconf(_SC_PAGESIZE));
    std::fclose(statm);
  }
  const auto as = static_cast<rlim_t>(mapped + memory_bytes);
  const rlimit as_limit{as, as};
  ::setrlimit(RLIMIT_AS, &as_limit);
#else
  (void)memory_bytes;
#endif
}

double cpu_seconds_of(const rusage& ru) {
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

std::string library_version() {
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  return std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(release);
}

}  // namespace

int superblock_version(const std::vector<char>& image) {
  return version_at_signature(image.size(), [&](std::uint64_t at, unsigned char* head) {
    std::memcpy(head, image.data() + at, 9);
    return true;
  });
}

int superblock_version(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!in || ec) return -1;
  return version_at_signature(size, [&](std::uint64_t at, unsigned char* head) {
    in.seekg(static_cast<std::streamoff>(at));
    return static_cast<bool>(in.read(reinterpret_cast<char*>(head), 9));
  });
}

void read_every_object(const File& f) {
  std::set<haddr_t> seen;  // hard links (and a damaged file's cycles) lead to an object once
  std::vector<std::string> todo{"/"};
  while (!todo.empty()) {
    const std::string path = todo.back();
    todo.pop_back();
    try {
      H5O_info_t info;
      {
        Handle obj(H5Oopen(f.id(), path.c_str(), H5P_DEFAULT));
        if (!obj.valid() || H5Oget_info2(obj.id(), &info, H5O_INFO_BASIC) < 0) continue;
      }
      if (!seen.insert(info.addr).second) continue;
      read_attributes(f, path);
      if (info.type == H5O_TYPE_DATASET) {
        read_dataset(f, path);
      } else if (info.type == H5O_TYPE_GROUP) {
        for (const std::string& name : members(f, path)) {
          const std::string p = child_path(path, name);
          if (exists(f, p)) todo.push_back(p);
        }
      }
    } catch (const Error&) {  // the readers meet the same error; the other objects are still read
    }
  }
}

Check run_checked(const std::function<void()>& open_and_read, double cpu_seconds, double memory_bytes) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error("cannot start a checking process: " + std::string(std::strerror(errno)));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error("cannot start a checking process: " + std::string(std::strerror(err)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    prepare_child(parent, cpu_seconds, memory_bytes);
    try {
      open_and_read();
    } catch (...) {  // an Error (or no memory within the bound): the parent meets it too, as one line
    }
    const char done = 'k';
    while (::write(fds[1], &done, 1) < 0 && errno == EINTR) {}
    ::_exit(0);  // no destructor, atexit handler or stdio flush of the parent's state
  }
  ::close(fds[1]);
  // The byte the child writes when it is done, or the end of the pipe when it dies. The
  // CPU bound ends a loop; a wall-clock bound (far longer: the machine may be busy) ends
  // a child that waits for ever, which no damage should make it do.
  const int wall_ms = static_cast<int>(std::min(1e9, 1000.0 * (60.0 + 20.0 * cpu_seconds)));
  pollfd p{fds[0], POLLIN, 0};
  int ready;
  while ((ready = ::poll(&p, 1, wall_ms)) < 0 && errno == EINTR) {}
  char done = 0;
  ssize_t got = 0;
  if (ready > 0)
    while ((got = ::read(fds[0], &done, 1)) < 0 && errno == EINTR) {}
  else
    ::kill(pid, SIGKILL);
  ::close(fds[0]);
  int status = 0;
  rusage ru{};
  while (::wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {}
  if (got == 1 && done == 'k') return Check::passed;
  if (ready <= 0) return Check::looped;
  if (WIFSIGNALED(status) &&
      (WTERMSIG(status) == SIGXCPU || (WTERMSIG(status) == SIGKILL && cpu_seconds_of(ru) >= std::floor(cpu_seconds))))
    return Check::looped;
  return Check::crashed;
}

void check_earlier_format(int superblock, double bytes, const std::function<File()>& open, const std::string& name) {
  if (superblock != 0 && superblock != 1) return;
  // Reading an intact file of this size whole takes a small part of this; a loop on
  // damaged metadata runs until it.
  const double cpu_seconds = 5.0 + std::floor(bytes / 8e6);
  const Check c = run_checked([&] { read_every_object(open()); }, cpu_seconds, 1e9 + bytes);
  if (c == Check::passed) return;
  const std::string what =
      c == Check::crashed ? "crashed reading it"
                          : "did not finish reading it in " + std::to_string(static_cast<int>(std::ceil(cpu_seconds))) +
                                " s of CPU time (a loop)";
  throw Error(name, "",
              "damaged file of HDF5's earlier format (superblock version " + std::to_string(superblock) +
                  ", no checksums): libhdf5 " + library_version() + " " + what +
                  " in a checking process; an intact copy can be rewritten in the checksummed format "
                  "with h5repack --low=2 --high=2 OLD NEW");
}

}  // namespace cdpile::io::h5
