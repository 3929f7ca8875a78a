// Files of HDF5's earlier format (superblock version 0 or 1, no checksums) are read whole in
// a child process and written anew in the checksummed format, which is what the readers
// read (io/h5_earlier.cpp): the superblock's version found where HDF5 looks for it, the
// child's verdicts, the rewritten file.
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
  h5::set_attr_ascii(f, "/", "kind", "pile");
  h5::set_attr_ascii(f, "/g", "text", "a variable-length string, in the global heap");
  h5::set_attr(f, "/g", "x0", 2.5);
  h5::write(f, "/g/x", std::vector<double>{1, 2, 3});
  H5Lcreate_soft("/g", f.id(), "link", H5P_DEFAULT, H5P_DEFAULT);
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
  const fs::path p =
      fs::temp_directory_path() / ("cdpile-earlier-" + std::to_string(::getpid()) + ".h5");
  const std::vector<char> image = earlier_format_image();
  std::ofstream(p, std::ios::binary)
      .write(image.data(), static_cast<std::streamsize>(image.size()));
  EXPECT_EQ(h5::superblock_version(p.string()), 0);
  EXPECT_EQ(h5::superblock_version("/nonexistent/cdpile.h5"), -1);
  fs::remove(p);
}

TEST(EarlierFormat, TheChildsEndIsTheVerdict) {
  const auto ok = h5::run_checked([] { return std::vector<char>{'a', '\0', 'b'}; }, 5, 1e9);
  EXPECT_EQ(ok.verdict, h5::Check::passed);
  EXPECT_EQ(ok.bytes, (std::vector<char>{'a', '\0', 'b'}));
  // more than a pipe holds at once
  const auto big = h5::run_checked([] { return std::vector<char>(1 << 20, 'x'); }, 5, 1e9);
  EXPECT_EQ(big.verdict, h5::Check::passed);
  EXPECT_EQ(big.bytes.size(), std::size_t{1} << 20);
  // an Error comes back as its text
  const auto failed =
      h5::run_checked([]() -> std::vector<char> { throw Error("f", "/g", "damaged"); }, 5, 1e9);
  EXPECT_EQ(failed.verdict, h5::Check::failed);
  EXPECT_EQ(failed.error, "f: /g: damaged");
  auto verdict = [](auto work) { return h5::run_checked(work, 1, 1e9).verdict; };
  EXPECT_EQ(verdict([]() -> std::vector<char> {
              std::raise(SIGSEGV);
              return {};
            }),
            h5::Check::crashed);
  EXPECT_EQ(verdict([]() -> std::vector<char> { std::abort(); }), h5::Check::crashed);
  EXPECT_EQ(verdict([]() -> std::vector<char> { std::_Exit(0); }),
            h5::Check::crashed);  // nothing written
  // an endless loop ends at the CPU bound (1 s of CPU time, however busy the machine)
  EXPECT_EQ(verdict([]() -> std::vector<char> {
              volatile bool go = true;
              while (go) {
              }
              return {};
            }),
            h5::Check::looped);
}

TEST(EarlierFormat, AnIntactFileIsRewrittenInTheChecksummedFormatAndRead) {
  const std::vector<char> image = earlier_format_image();
  const h5::File old = h5::open_image_unchecked(image, "earlier.h5");
  const std::vector<char> rewritten = h5::rewrite_in_current_format(old);
  EXPECT_EQ(h5::superblock_version(rewritten), 3);
  // what open_image returns for the earlier format: the rewritten file, the same content
  const h5::File f = h5::open_image(image, "earlier.h5");
  EXPECT_EQ(f.name(), "earlier.h5");
  EXPECT_EQ(h5::attr_string(f, "/", "kind"), "pile");
  EXPECT_EQ(h5::attr_string(f, "/g", "text"), "a variable-length string, in the global heap");
  EXPECT_EQ(h5::attr_double(f, "/g", "x0"), 2.5);
  EXPECT_EQ(h5::read<double>(f, "/g/x", {3}), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(h5::members(f, "/"), (std::vector<std::string>{"g", "link"}));
  EXPECT_EQ(h5::read<double>(f, "/link/x", {3}),
            (std::vector<double>{1, 2, 3}));  // the soft link kept
}

TEST(EarlierFormat, ACrashWhileRewritingIsOneErrorNamingTheFile) {
  try {
    h5::open_earlier_format(
        0, 1000,
        [&]() -> h5::File {
          std::raise(SIGSEGV);
          return {};
        },
        "old.h5");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("old.h5: damaged file of HDF5's earlier format (superblock version 0, no "
                         "checksums): libhdf5 ",
                         0),
              0u)
        << what;
    EXPECT_NE(what.find("crashed reading it in a separate process"), std::string::npos) << what;
    EXPECT_NE(what.find("h5repack --low=2 --high=2"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  // a file of this version's format is opened in this process, without a child
  h5::File mem = h5::create_in_memory("mem");
  const std::vector<char> image = h5::image_of(mem);
  EXPECT_NO_THROW(h5::open_image(image, "new.h5"));
}
