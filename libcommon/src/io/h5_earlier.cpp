// Files of HDF5's earlier format (superblock version 0 or 1: what cdpile wrote before it
// asked for the 1.10 format, and what most other programs still write by default).
//
// Nothing in that format is checksummed, and libhdf5 1.10.8 follows a damaged header,
// heap or B-tree wherever it points: the fuzzer made it crash (SIGSEGV, SIGBUS, SIGFPE,
// heap-corruption aborts) or loop for ever inside single library calls, before any
// check of cdpile's could run (docs/fuzzing.md, "Findings"). No check outside the
// library can see such damage coming, but a process can survive it in another process.
// Such a file is never parsed in the tool's process: a forked child, bounded in CPU time
// and memory, reads it and writes it anew in this version's format (checksummed, every
// header encoded by HDF5 itself), and the tool reads that image. Reading it in the tool
// after a child read it without harm is not enough: the fuzzer found inputs on which
// HDF5 reads memory outside its buffers, so that the same calls crash or not depending
// on what the heap holds at the time (docs/fuzzing.md).
//
// Refusing the earlier format outright would be simpler, but every run and product
// made before this version is in it, and nearly all of them are intact: the child keeps
// them readable for the price of copying each one in memory (docs/cli.md, "What is
// refused").
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
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define CDPILE_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CDPILE_ADDRESS_SANITIZER 1
#endif
#endif

// Set by libFuzzer (and callable by anyone) to run when a sanitizer reports an error: in
// the child that rewrites a file it would save the input as a crash of the harness, though the
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

/// Copies the attributes of `path` in `src` onto the same object of `dst`, each read in
/// its native memory type (variable-length strings as C strings) and written with its
/// file type.
void copy_attributes(const File& src, const File& dst, const std::string& path) {
  for (const std::string& name : attr_names(src, path)) {
    auto fail = [&](const std::string& what) {
      throw Error(src.name(), path, "attribute '" + name + "': " + what);
    };
    Handle obj(H5Oopen(src.id(), path.c_str(), H5P_DEFAULT));
    Handle a(obj.valid() ? H5Aopen(obj.id(), name.c_str(), H5P_DEFAULT) : H5I_INVALID_HID);
    if (!a.valid()) fail("cannot open");
    Handle ftype(H5Aget_type(a.id())), space(H5Aget_space(a.id()));
    Handle mtype(ftype.valid() ? H5Tget_native_type(ftype.id(), H5T_DIR_DEFAULT) : H5I_INVALID_HID);
    const hssize_t n = space.valid() ? H5Sget_simple_extent_npoints(space.id()) : -1;
    if (!mtype.valid() || n < 0) fail("cannot read");
    const double size = static_cast<double>(n) * static_cast<double>(H5Tget_size(mtype.id()));
    if (size > 1e9) fail("too large (" + std::to_string(n) + " elements)");  // a damaged count
    std::vector<unsigned char> buf(static_cast<std::size_t>(size) + 1);
    if (n > 0 && H5Aread(a.id(), mtype.id(), buf.data()) < 0) fail("cannot read");
    Handle to(H5Oopen(dst.id(), path.c_str(), H5P_DEFAULT));
    Handle b(to.valid() ? H5Acreate2(to.id(), name.c_str(), ftype.id(), space.id(), H5P_DEFAULT,
                                     H5P_DEFAULT)
                        : H5I_INVALID_HID);
    const bool written = b.valid() && (n == 0 || H5Awrite(b.id(), mtype.id(), buf.data()) >= 0);
    if (n > 0 && (H5Tdetect_class(mtype.id(), H5T_VLEN) > 0 || H5Tis_variable_str(mtype.id()) > 0))
      H5Dvlen_reclaim(mtype.id(), space.id(), H5P_DEFAULT, buf.data());
    if (!written) fail("cannot copy");
  }
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
    if (std::fscanf(statm, "%lu", &pages) == 1)
      mapped = static_cast<double>(pages) * static_cast<double>(::sysconf(_SC_PAGESIZE));
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

std::vector<char> rewrite_in_current_format(const File& src) {
  File dst = create_in_memory(src.name());
  copy_attributes(src, dst, "/");
  for (const std::string& name : members(src, "/")) {
    H5L_info_t link;
    if (H5Lget_info(src.id(), name.c_str(), &link, H5P_DEFAULT) < 0)
      throw Error(src.name(), "/" + name, "cannot read the link");
    if (link.type == H5L_TYPE_SOFT) {  // kept as a link, as H5Ocopy keeps those below the root
      std::vector<char> target(std::min<std::size_t>(link.u.val_size, 1 << 16) + 1, '\0');
      if (H5Lget_val(src.id(), name.c_str(), target.data(), target.size(), H5P_DEFAULT) < 0 ||
          H5Lcreate_soft(target.data(), dst.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0)
        throw Error(src.name(), "/" + name, "cannot copy the link");
      continue;
    }
    if (H5Ocopy(src.id(), name.c_str(), dst.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0)
      throw Error(src.name(), "/" + name, "cannot read (damaged?)");
  }
  return image_of(dst);
}

Checked run_checked(const std::function<std::vector<char>()>& work, double cpu_seconds,
                    double memory_bytes) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw Error("cannot start a process to read a file of the earlier format: " +
                std::string(std::strerror(errno)));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw Error("cannot start a process to read a file of the earlier format: " +
                std::string(std::strerror(err)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    prepare_child(parent, cpu_seconds, memory_bytes);
    auto send = [&](const char* data, std::size_t n) {
      for (std::size_t done = 0; done < n;) {
        const ssize_t w = ::write(fds[1], data + done, n - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) ::_exit(1);
        done += static_cast<std::size_t>(w);
      }
    };
    // 'k' and the bytes, or 'e' and an Error's text (none: out of memory).
    try {
      const std::vector<char> bytes = work();
      send("k", 1);
      send(bytes.data(), bytes.size());
    } catch (const Error& e) {
      const std::string text = std::string("e") + e.what();
      send(text.data(), text.size());
    } catch (const std::bad_alloc&) {
      send("e", 1);
    }
    ::_exit(0);  // no destructor, atexit handler or stdio flush of the parent's state
  }
  ::close(fds[1]);
  // Everything the child writes, until it closes the pipe by ending. The CPU bound ends a
  // loop; a wall-clock bound (far longer: the machine may be busy) ends a child that
  // waits for ever, which no damage should make it do.
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(60.0 + 20.0 * cpu_seconds);
  std::vector<char> got;
  bool timed_out = false;
  char buf[1 << 16];
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    pollfd p{fds[0], POLLIN, 0};
    const int ready =
        left > 0 ? ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1 << 30))) : 0;
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) {
      timed_out = true;
      break;
    }
    const ssize_t r = ::read(fds[0], buf, sizeof buf);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    got.insert(got.end(), buf, buf + r);
  }
  if (timed_out) ::kill(pid, SIGKILL);
  ::close(fds[0]);
  int status = 0;
  rusage ru{};
  while (::wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {
  }
  Checked c;
  const bool ended = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (timed_out || (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU ||
                                            (WTERMSIG(status) == SIGKILL &&
                                             cpu_seconds_of(ru) >= std::floor(cpu_seconds))))) {
    c.verdict = Check::looped;
  } else if (ended && !got.empty() && got[0] == 'k') {
    c.verdict = Check::passed;
    got.erase(got.begin());  // in place: the image may be large
    c.bytes = std::move(got);
  } else if (ended && !got.empty() && got[0] == 'e') {
    c.verdict = Check::failed;
    c.error.assign(got.begin() + 1, got.end());
  } else {
    c.verdict = Check::crashed;
  }
  return c;
}

File open_earlier_format(int superblock, double bytes, const std::function<File()>& open,
                         const std::string& name) {
  // Rewriting an intact file of this size takes a small part of this; a loop on damaged
  // metadata runs until it.
  const double cpu_seconds = 5.0 + std::floor(bytes / 8e6);
  // The child holds the file's data twice at most (what it reads, what it writes).
  Checked c;
  try {
    c = run_checked([&] { return rewrite_in_current_format(open()); }, cpu_seconds,
                    1e9 + 3 * bytes);
  } catch (const Error& e) {  // no pipe or no process: the file named, as every error
    throw Error(name, "", e.what());
  }
  if (c.verdict == Check::passed) {
    auto image = std::make_shared<const std::vector<char>>(std::move(c.bytes));
    return File(open_image_unchecked(*image, name), image);
  }
  if (c.verdict == Check::failed)
    throw Error(
        c.error.empty()
            ? Error::join(name, "", "too large to read within 1 GB of memory plus 3 times its size")
            : c.error);
  const std::string what = c.verdict == Check::crashed
                               ? "crashed reading it"
                               : "did not finish reading it in " +
                                     std::to_string(static_cast<int>(cpu_seconds)) +
                                     " s of CPU time (a loop)";
  throw Error(
      name, "",
      "damaged file of HDF5's earlier format (superblock version " + std::to_string(superblock) +
          ", no checksums): libhdf5 " + library_version() + " " + what +
          " in a separate process; an intact copy can be rewritten in the checksummed format "
          "with h5repack --low=2 --high=2 OLD NEW");
}

}  // namespace cdpile::io::h5

// The variable-length string attributes of a file of this version's format. Their
// headers are checksummed, but their strings sit in a global heap that is not, and
// libhdf5 1.10.8 loops for ever in H5HG__protect on some damaged heaps (fuzz_run,
// docs/fuzzing.md); they stay variable-length, as the H5MD units module wants. So the
// tool's process never reads them: a child lists and reads all of them once, when the
// file is opened, and sends their values back; attr_strings answers from those. The
// listing is done in the child too: on a damaged file, H5Ovisit's error path loses an
// object header inside libhdf5 (424 bytes, reported by LeakSanitizer), and the tool's
// process should not walk a file it has not yet found sound.
namespace cdpile::io::h5 {

namespace {

struct StringAttribute {
  haddr_t address;
  std::string path, name;
};

/// The variable-length string attributes of every object of `f`, found from the
/// (checksummed) object headers alone. Objects that cannot be read are skipped: the
/// reader meets the damage itself, with its own message, if it needs them.
std::vector<StringAttribute> string_attributes_of(const File& f) {
  std::vector<StringAttribute> out;
  auto visit = [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    auto& found = *static_cast<std::vector<StringAttribute>*>(data);
    const std::string path =
        std::strcmp(name, ".") == 0 ? std::string("/") : "/" + std::string(name);
    Handle obj(H5Oopen_by_addr(root, info->addr));
    for (hsize_t k = 0; obj.valid() && k < info->num_attrs; ++k) {
      Handle a(
          H5Aopen_by_idx(obj.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, H5P_DEFAULT, H5P_DEFAULT));
      Handle t(a.valid() ? H5Aget_type(a.id()) : H5I_INVALID_HID);
      if (!t.valid() || H5Tget_class(t.id()) != H5T_STRING || H5Tis_variable_str(t.id()) <= 0)
        continue;
      const ssize_t len = H5Aget_name(a.id(), 0, nullptr);
      if (len < 0) continue;
      std::string attr(static_cast<std::size_t>(len), '\0');
      H5Aget_name(a.id(), attr.size() + 1, attr.data());
      found.push_back({info->addr, path, attr});
    }
    return 0;
  };
  H5Ovisit2(f.id(), H5_INDEX_NAME, H5_ITER_INC, visit, &out, H5O_INFO_BASIC | H5O_INFO_NUM_ATTRS);
  return out;
}

void put_u64(std::vector<char>& out, std::uint64_t x) {
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<char>((x >> (8 * b)) & 0xff));
}
void put_text(std::vector<char>& out, const std::string& s) {
  put_u64(out, s.size());
  out.insert(out.end(), s.begin(), s.end());
}

/// In the child: every variable-length string attribute of `f` with its values, as
/// address, name, count and texts.
std::vector<char> read_in_child(const File& f) {
  std::vector<char> out;
  for (const StringAttribute& s : string_attributes_of(f)) {
    auto fail = [&] {
      throw Error(f.name(), s.path,
                  "damaged HDF5 file: cannot read attribute '" + s.name +
                      "' (global heap of its string attributes)");
    };
    Handle obj(H5Oopen_by_addr(f.id(), s.address));
    Handle a(obj.valid() ? H5Aopen(obj.id(), s.name.c_str(), H5P_DEFAULT) : H5I_INVALID_HID);
    Handle space(a.valid() ? H5Aget_space(a.id()) : H5I_INVALID_HID),
        ftype(a.valid() ? H5Aget_type(a.id()) : H5I_INVALID_HID);
    const hssize_t n = space.valid() ? H5Sget_simple_extent_npoints(space.id()) : -1;
    if (n < 0 || !ftype.valid() || n > (1 << 24)) fail();
    Handle mt(H5Tcopy(H5T_C_S1));
    H5Tset_size(mt.id(), H5T_VARIABLE);
    H5Tset_cset(mt.id(), H5Tget_cset(ftype.id()));  // HDF5 does not convert between ASCII and UTF-8
    std::vector<char*> p(static_cast<std::size_t>(n), nullptr);
    if (n > 0 && H5Aread(a.id(), mt.id(), p.data()) < 0) fail();
    put_u64(out, s.address);
    put_text(out, s.name);
    put_u64(out, static_cast<std::uint64_t>(n));
    for (const char* v : p) put_text(out, v ? v : "");
    // no H5Dvlen_reclaim: the child ends now
  }
  return out;
}

}  // namespace

void read_string_attributes(File& f) {
  // The headers and strings are a few bytes each: a small part of a second even on a
  // busy machine.
  const double cpu_seconds = 5.0;
  Checked c;
  try {
    c = run_checked([&] { return read_in_child(f); }, cpu_seconds, 1e9);
  } catch (const Error& e) {
    throw Error(f.name(), "", e.what());
  }
  if (c.verdict == Check::failed)
    throw Error(c.error.empty() ? Error::join(f.name(), "",
                                              "damaged HDF5 file: out of memory reading its string "
                                              "attributes (global heap of its string attributes)")
                                : c.error);
  if (c.verdict != Check::passed)
    throw Error(
        f.name(), "",
        "damaged HDF5 file: libhdf5 " + library_version() + " " +
            (c.verdict == Check::crashed
                 ? std::string("crashed reading it")
                 : "did not finish reading it in " + std::to_string(static_cast<int>(cpu_seconds)) +
                       " s of CPU time (a loop)") +
            " in a separate process (global heap of its string attributes)");
  auto values = std::make_shared<File::StringAttributes>();
  const std::vector<char>& b = c.bytes;
  std::size_t at = 0;
  auto short_reply = [&] {
    throw Error(f.name(), "",
                "damaged HDF5 file: a short reply from the process reading it (global heap of its "
                "string attributes)");
  };
  auto u64 = [&] {
    if (b.size() - at < 8) short_reply();
    std::uint64_t x = 0;
    for (int k = 0; k < 8; ++k)
      x |= std::uint64_t{static_cast<unsigned char>(b[at + static_cast<std::size_t>(k)])}
           << (8 * k);
    at += 8;
    return x;
  };
  auto text = [&] {
    const std::uint64_t n = u64();
    if (b.size() - at < n) short_reply();
    std::string s(b.data() + at, static_cast<std::size_t>(n));
    at += static_cast<std::size_t>(n);
    return s;
  };
  while (at < b.size()) {
    const auto address = static_cast<haddr_t>(u64());
    std::string name = text();
    const std::uint64_t n = u64();
    std::vector<std::string> v;
    for (std::uint64_t k = 0; k < n; ++k) v.push_back(text());
    (*values)[{address, std::move(name)}] = std::move(v);
  }
  f.set_string_attributes(std::move(values));
}

}  // namespace cdpile::io::h5
