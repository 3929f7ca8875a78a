// Inputs that are not regular files: a FIFO (or a process substitution, /dev/fd/N) can be
// read once from its start, so io::Input reads it whole, as it reads standard input.
#include "cdpile/error.hpp"
#include "cdpile/io/files.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;
using namespace cdpile;

namespace {
/// A FIFO in a scratch folder, with a thread writing `bytes` into it.
struct Fifo {
  fs::path dir, path;
  std::thread writer;
  explicit Fifo(std::string bytes) {
    dir = fs::temp_directory_path() /
          ("cdpile-fifo-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    fs::create_directories(dir);
    path = dir / "pipe";
    if (::mkfifo(path.c_str(), 0600) != 0) throw std::runtime_error("mkfifo failed");
    writer =
        std::thread([p = path, b = std::move(bytes)] { std::ofstream(p, std::ios::binary) << b; });
  }
  ~Fifo() {
    writer.join();
    fs::remove_all(dir);
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
};
}  // namespace

TEST(Input, AFifoIsReadWholeLikeStandardInput) {
  // an HDF5 image through the FIFO opens as a file
  io::h5::File mem = io::h5::create_in_memory("mem");
  io::h5::create_group(mem, "/g");
  const std::vector<char> image = io::h5::image_of(mem);
  {
    Fifo f(std::string(image.begin(), image.end()));
    const io::Input in(f.path.string());
    EXPECT_TRUE(in.is_hdf5());
    EXPECT_EQ(in.name(), f.path.string());
  }
  // text too
  {
    Fifo f("a\tb\n1\t2\n");
    const io::Input in(f.path.string());
    EXPECT_FALSE(in.is_hdf5());
    EXPECT_EQ(in.text(), "a\tb\n1\t2\n");
  }
  // nothing written: one line naming the input
  {
    Fifo f("");
    try {
      io::Input in(f.path.string());
      ADD_FAILURE() << "an empty FIFO was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()),
                f.path.string() + ": no data (did the tool writing it fail?)");
    }
  }
}
