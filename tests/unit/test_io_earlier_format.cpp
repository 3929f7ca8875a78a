// Files of HDF5's earlier format (superblock version 0 or 1, no checksums) are read whole in
// a child process before the readers touch them (io/h5_earlier.cpp): the superblock's
// version found where HDF5 looks for it, the child's verdicts, the walk over every object.
#include "cdpile/error.hpp"
#include "cdpile/io/h5.hpp"

#include <gtest/gtest.h>

#include <H5LTpublic.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace cdpile;
namespace h5 = cdpile::io::h5;

namespace {
/// An image in HDF5's default format (what cdpile wrote before it asked for 1.10's):
/// superblock version 0.
std::vector<char> earlier_format_image() {
  h5::silence_errors();
  h5::Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_fapl_core(fapl.id(), 1 << 16, 0);
  h5::File f(h5::Handle(H5Fcreate("earlier", H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id())), "earlier");
  h5::create_group(f, "/g");
  h5::set_attr_ascii(f, "/g", "text", "a variable-length string, in the global heap");
  h5::write(f, "/g/x", std::vector<double>{1, 2, 3});
  H5Fflush(f.id(), H5F_SCOPE_GLOBAL);
  const ssize_t size = H5Fget_file_image(f.id(), nullptr, 0);
  std::vector<char> image(static_cast<std::size_t>(size));
  H5Fget_file_image(f.id(), image.data(), image.size());
  return image;
}
}  // namespace

TEST(EarlierFormat, SuperblockVersionIsReadWhereHdf5LooksForIt) {
  EXPECT_EQ(h5::superblock_version(earlier_format_image()), 0);
  // after a user block: the signature at 512 (or 1024, 2048, ...), as HDF5 finds it
  std::vector<char> with_userblock(512, 'u');
  const std::vector<char> image0 = earlier_format_image();
  with_userblock.insert(with_userblock.end(), image0.begin(), image0.end());
  EXPECT_EQ(h5::superblock_version(with_userblock), 0);
  with_userblock.insert(with_userblock.begin(), 512, 'u');
  EXPECT_EQ(h5::superblock_version(with_userblock), 0);
  with_userblock.insert(with_userblock.begin(), 100, 'u');  // 1124: not where HDF5 looks
  EXPECT_EQ(h5::superblock_version(with_userblock), -1);
  // this version's files: superblock 3, not checked
  h5::File mem = h5::create_in_memory("mem");
  EXPECT_EQ(h5::superblock_version(h5::image_of(mem)), 3);
  EXPECT_EQ(h5::superblock_version(std::vector<char>{'a', 'b'}), -1);
  EXPECT_EQ(h5::superblock_version(std::vector<char>(4096, '\0')), -1);
  // from a path, the same
  const fs::path p = fs::temp_directory_path() / ("cdpile-earlier-" + std::to_string(::getpid()) + ".h5");
  const std::vector<char> image = earlier_format_image();
  std::ofstream(p, std::ios::binary).write(image.data(), static_cast<std::streamsize>(image.size()));
  EXPECT_EQ(h5::superblock_version(p.string()), 0);
  EXPECT_EQ(h5::superblock_version("/nonexistent/cdpile.h5"), -1);
  fs::remove(p);
}

TEST(EarlierFormat, TheChildsEndIsTheVerdict) {
  EXPECT_EQ(h5::run_checked([] {}, 5, 1e9), h5::Check::passed);
  // an Error is the readers' to report, in the parent
  EXPECT_EQ(h5::run_checked([] { throw Error("f", "", "damaged"); }, 5, 1e9), h5::Check::passed);
  EXPECT_EQ(h5::run_checked([] { std::raise(SIGSEGV); }, 5, 1e9), h5::Check::crashed);
  EXPECT_EQ(h5::run_checked([] { std::abort(); }, 5, 1e9), h5::Check::crashed);
  EXPECT_EQ(h5::run_checked([] { std::_Exit(3); }, 5, 1e9), h5::Check::crashed);
  // an endless loop ends at the CPU bound (1 s of CPU time, however busy the machine)
  EXPECT_EQ(h5::run_checked([] { volatile bool go = true; while (go) {} }, 1, 1e9), h5::Check::looped);
}

TEST(EarlierFormat, AnIntactFileOfTheEarlierFormatIsCheckedThenRead) {
  const std::vector<char> image = earlier_format_image();
  const h5::File f = h5::open_image(image, "earlier.h5");
  EXPECT_EQ(h5::attr_string(f, "/g", "text"), "a variable-length string, in the global heap");
  EXPECT_EQ(h5::read<double>(f, "/g/x", {3}), (std::vector<double>{1, 2, 3}));
}

TEST(EarlierFormat, ACrashWhileCheckingIsOneErrorNamingTheFile) {
  try {
    h5::check_earlier_format(0, 1000, [&]() -> h5::File { std::raise(SIGSEGV); return {}; }, "old.h5");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("old.h5: damaged file of HDF5's earlier format (superblock version 0, no checksums): libhdf5 ", 0), 0u) << what;
    EXPECT_NE(what.find("crashed reading it in a checking process"), std::string::npos) << what;
    EXPECT_NE(what.find("h5repack --low=2 --high=2"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  // this version's format (superblock 2 or 3) is never opened in a child
  EXPECT_NO_THROW(h5::check_earlier_format(3, 1000, [&]() -> h5::File { std::raise(SIGSEGV); return {}; }, "new.h5"));
  EXPECT_NO_THROW(h5::check_earlier_format(-1, 1000, [&]() -> h5::File { std::raise(SIGSEGV); return {}; }, "text.tsv"));
}

TEST(EarlierFormat, TheWalkEndsOnACycleAndGoesOnAfterAnError) {
  h5::File f = h5::create_in_memory("walk");
  h5::create_group(f, "/a/b");
  h5::hard_link(f, "/", "/a/b/root");  // a cycle: / -> a -> b -> root = /
  h5::write(f, "/a/nan", std::vector<double>{1, std::nan("")});
  h5::write(f, "/a/b/x", std::vector<std::int32_t>{1, 2});
  h5::set_attr(f, "/a", "n", std::int64_t{4});
  EXPECT_NO_THROW(h5::read_every_object(f));
}
