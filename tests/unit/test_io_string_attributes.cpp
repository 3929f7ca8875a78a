// Variable-length string attributes of a file of this version's format are read by a
// child process when the file is opened (io/h5_earlier.cpp, read_string_attributes): their
// global heap carries no checksum, and libhdf5 1.10 loops for ever on some damaged ones.
// What the readers get from the child equals what H5Aread gives on an intact file.
#include "cdpile/error.hpp"
#include "cdpile/io/h5.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace cdpile;
namespace h5 = cdpile::io::h5;

namespace {
/// An image of this version's format with variable-length string attributes (ASCII and
/// UTF-8, one and several), a fixed-length one and a number, on the root, a group and a
/// dataset reached by two links.
std::vector<char> image_with_strings() {
  h5::File f = h5::create_in_memory("strings");
  h5::create_group(f, "/g/h");
  h5::write(f, "/g/x", std::vector<double>{1, 2, 3});
  h5::hard_link(f, "/g/x", "/y");
  h5::set_attr_ascii(f, "/", "system", "SI");
  h5::set_attr_ascii(f, "/g/x", "unit", "m s-1");
  h5::set_attr_ascii(f, "/g/h", "empty", "");
  h5::set_attr(f, "/g", "fixed", std::string("fixed-length"));
  h5::set_attr(f, "/g", "x0", 2.5);
  {  // a UTF-8 list of three
    h5::Handle obj(H5Oopen(f.id(), "/g", H5P_DEFAULT));
    h5::Handle t(H5Tcopy(H5T_C_S1));
    H5Tset_size(t.id(), H5T_VARIABLE);
    H5Tset_cset(t.id(), H5T_CSET_UTF8);
    const hsize_t n = 3;
    h5::Handle space(H5Screate_simple(1, &n, nullptr));
    h5::Handle a(H5Acreate2(obj.id(), "labels", t.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT));
    const char* v[3] = {"\xc2\xb5m", "", "grain"};
    H5Awrite(a.id(), t.id(), v);
  }
  return h5::image_of(f);
}
}  // namespace

TEST(StringAttributes, ReadByTheChildEqualWhatH5AreadGives) {
  const std::vector<char> image = image_with_strings();
  const h5::File direct = h5::open_image_unchecked(image, "strings.h5");  // H5Aread in process
  ASSERT_EQ(direct.string_attributes(), nullptr);
  const h5::File checked = h5::open_image(image, "strings.h5");
  ASSERT_NE(checked.string_attributes(), nullptr);
  EXPECT_EQ(checked.string_attributes()->size(), 4u);  // system, unit, empty, labels
  for (const auto& [path, name] :
       std::vector<std::pair<std::string, std::string>>{{"/", "system"},
                                                        {"/g/x", "unit"},
                                                        {"/y", "unit"},
                                                        {"/g/h", "empty"},
                                                        {"/g", "labels"},
                                                        {"/g", "fixed"}})
    EXPECT_EQ(h5::attr_strings(checked, path, name), h5::attr_strings(direct, path, name))
        << path << " " << name;
  EXPECT_EQ(h5::attr_strings(checked, "/g", "labels"),
            (std::vector<std::string>{"\xc2\xb5m", "", "grain"}));
  EXPECT_EQ(h5::attr_string(checked, "/y", "unit"), "m s-1");
  EXPECT_EQ(h5::attr_double(checked, "/g", "x0"), 2.5);

  // The same through a file on disk (open_read).
  const fs::path path =
      fs::temp_directory_path() / ("cdpile-strings-" + std::to_string(::getpid()) + ".h5");
  std::ofstream(path, std::ios::binary)
      .write(image.data(), static_cast<std::streamsize>(image.size()));
  {
    const h5::File f = h5::open_read(path.string(), "strings.h5");
    EXPECT_EQ(h5::attr_string(f, "/g/x", "unit"), "m s-1");
    EXPECT_EQ(h5::attr_string(f, "/", "system"), "SI");
  }
  fs::remove(path);
}

TEST(StringAttributes, NoneGiveAnEmptyMap) {
  h5::File f = h5::create_in_memory("plain");
  h5::set_attr(f, "/", "kind", std::string("pile"));
  const std::vector<char> image = h5::image_of(f);
  const h5::File g = h5::open_image(image, "plain.h5");
  ASSERT_NE(g.string_attributes(), nullptr);
  EXPECT_TRUE(g.string_attributes()->empty());
  EXPECT_EQ(h5::attr_string(g, "/", "kind"), "pile");
}

TEST(StringAttributes, ADamagedGlobalHeapIsOneErrorNotAHang) {
  // The run fuzz_run found (tests/fuzz/run/): HDF5 loops for ever in H5HG__protect in
  // process; the child's CPU bound ends it.
  const fs::path gz = fs::path(CDPILE_TEST_DATA) / "../fuzz/run/run-unit-global-heap-hang.h5.gz";
  std::FILE* in = ::popen(("gunzip -c '" + gz.string() + "'").c_str(), "r");
  ASSERT_NE(in, nullptr);
  std::vector<char> image;
  char buf[1 << 16];
  for (std::size_t r; (r = std::fread(buf, 1, sizeof buf, in)) > 0;)
    image.insert(image.end(), buf, buf + r);
  ASSERT_EQ(::pclose(in), 0);
  ASSERT_GT(image.size(), 1000u);
  try {
    h5::open_image(image, "bad.h5");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("bad.h5: damaged HDF5 file: ", 0), 0u) << what;
    EXPECT_NE(what.find("(global heap of its string attributes)"), std::string::npos) << what;
  }
}
