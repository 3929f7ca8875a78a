// Every number read is checked against the types the schema names before HDF5 converts
// it (io/h5.cpp, check_number_type; docs/schema.md, "Types"): one test per property of a
// stored type (class, size, precision, bit offset, sign, byte order, the float's fields),
// the data space (rank, extent, a null space), the attributes and their text (class,
// character set, padding); and the damaged file of
// the earlier format that made correlate die with SIGBUS in HDF5's conversion. A byte order
// other than little- or big-endian cannot be stored: HDF5 1.10 decodes a float written in
// VAX order as big-endian, so the first test's two orders are all a file can claim.
#include "cdpile/error.hpp"
#include "cdpile/io/h5.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace cdpile;
namespace h5 = cdpile::io::h5;

namespace {

/// A dataset /x of `n` elements stored with file type `file_type`, written from `data` of
/// memory type `mem_type` (HDF5 converts on the way in).
void add_dataset(const h5::File& f, hid_t file_type, hid_t mem_type, const void* data, hsize_t n,
                 const char* path = "/x") {
  h5::Handle space(H5Screate_simple(1, &n, nullptr));
  h5::Handle d(
      H5Dcreate2(f.id(), path, file_type, space.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  ASSERT_TRUE(d.valid());
  ASSERT_GE(H5Dwrite(d.id(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0);
}

/// The image of an in-memory file that `build` filled. open_image reads the image in
/// place: the test keeps it alive while the file is open.
template <class Build>
std::vector<char> image_with(Build&& build) {
  h5::File f = h5::create_in_memory("types.h5");
  build(f);
  return h5::image_of(f);
}

/// The message of the Error that `read` throws, or "" if it throws none.
template <class Read>
std::string refusal(Read&& read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// A 32-bit integer type altered by `alter` (precision, offset, size, ...).
template <class Alter>
h5::Handle int32_altered(Alter&& alter) {
  h5::Handle t(H5Tcopy(H5T_STD_I32LE));
  alter(t.id());
  return t;
}

const std::vector<std::int32_t> kInts = {1, 2, 3};

/// The image of a file of the earlier format (superblock version 0: no checksums) that
/// `build` filled, with the bytes `from` found in it replaced by `to`: damage that HDF5
/// opens without complaint, and that the child rewriting such files copies as it is.
template <class Build>
std::vector<char> earlier_format_with(Build&& build, const std::vector<char>& from,
                                      const std::vector<char>& to) {
  std::vector<char> bytes;
  {
    h5::Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    H5Pset_fapl_core(fapl.id(), 1 << 16, 0);
    H5Pset_libver_bounds(fapl.id(), H5F_LIBVER_EARLIEST, H5F_LIBVER_LATEST);
    const h5::File w(h5::Handle(H5Fcreate(("cdpile-earlier-" + std::to_string(::getpid())).c_str(),
                                          H5F_ACC_TRUNC, H5P_DEFAULT, fapl.id())),
                     "old.h5");
    EXPECT_TRUE(w.valid());
    build(w);
    H5Fflush(w.id(), H5F_SCOPE_LOCAL);
    bytes.resize(static_cast<std::size_t>(H5Fget_file_image(w.id(), nullptr, 0)));
    H5Fget_file_image(w.id(), bytes.data(), bytes.size());
  }
  const auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
  EXPECT_NE(at, bytes.end());
  if (at != bytes.end()) std::copy(to.begin(), to.end(), at);
  EXPECT_EQ(h5::superblock_version(bytes), 0);
  return bytes;
}

}  // namespace

TEST(StoredTypes, StandardTypesOfEitherByteOrderReadAsTheirValues) {
  const std::vector<double> v = {0.5, -2.25, 1e300};
  const std::vector<float> vf = {0.5f, -2.25f, 3.0e38f};
  const std::vector<std::int64_t> vi = {-5, 0, std::int64_t{1} << 40};
  const std::vector<char> image = image_with([&](const h5::File& w) {
    add_dataset(w, H5T_IEEE_F64BE, H5T_NATIVE_DOUBLE, v.data(), 3, "/f64be");
    add_dataset(w, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, vf.data(), 3, "/f32le");
    add_dataset(w, H5T_STD_I64BE, H5T_NATIVE_INT64, vi.data(), 3, "/i64be");
    add_dataset(w, H5T_STD_U16BE, H5T_NATIVE_INT32, kInts.data(), 3, "/u16be");
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(h5::read<double>(f, "/f64be", {3}), v);
  EXPECT_EQ(h5::read<double>(f, "/f32le", {3}),
            (std::vector<double>{0.5, -2.25, static_cast<double>(3.0e38f)}));
  EXPECT_EQ(h5::read<std::int64_t>(f, "/i64be", {3}), vi);
  EXPECT_EQ(h5::read<double>(f, "/i64be", {3}),
            (std::vector<double>{-5.0, 0.0, 1099511627776.0}));  // exact below 2^53
  EXPECT_EQ(h5::read<std::int64_t>(f, "/u16be", {3}), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(h5::read_rows<std::int32_t>(f, "/u16be", 1, 2), (std::vector<std::int32_t>{2, 3}));
}

TEST(StoredTypes, AClassThatIsNotANumberIsRefused) {
  const std::vector<char> image = image_with([](const h5::File& w) {
    h5::Handle t(H5Tcopy(H5T_C_S1));
    H5Tset_size(t.id(), 4);
    const char text[] = "abcdefghijkl";
    add_dataset(w, t.id(), t.id(), text, 3);
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/x", {3}); }),
            "types.h5: /x: expected numbers, found a 4-byte text");
  EXPECT_EQ(refusal([&] { h5::read_rows<std::int32_t>(f, "/x", 0, 1); }),
            "types.h5: /x: expected integers, found a 4-byte text");
}

TEST(StoredTypes, AFloatIsNotReadAsAnInteger) {
  const std::vector<double> v = {1, 2, 3};
  const std::vector<char> image = image_with(
      [&](const h5::File& w) { add_dataset(w, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), 3); });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::read<std::int64_t>(f, "/x", {3}); }),
            "types.h5: /x: expected integers, found a 8-byte float of 64 bits at bit offset 0, "
            "little-endian");
}

TEST(StoredTypes, AnIntegerOfOddSizeIsRefused) {
  const h5::Handle t = int32_altered([](hid_t id) { H5Tset_size(id, 3); });
  const std::vector<char> image = image_with(
      [&](const h5::File& w) { add_dataset(w, t.id(), H5T_NATIVE_INT32, kInts.data(), 3); });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/x", {3}); }),
            "types.h5: /x: stored as a 3-byte signed integer of 24 bits at bit offset 0, "
            "little-endian, not a standard integer or IEEE float type (damaged, or written by "
            "another program): refused before conversion");
}

TEST(StoredTypes, APrecisionShorterThanTheSizeIsRefused) {
  const h5::Handle t = int32_altered([](hid_t id) { H5Tset_precision(id, 12); });
  const std::vector<char> image = image_with(
      [&](const h5::File& w) { add_dataset(w, t.id(), H5T_NATIVE_INT32, kInts.data(), 3); });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_NE(refusal([&] {
              h5::read<double>(f, "/x", {3});
            }).find("/x: stored as a 4-byte signed integer of 12 bits at bit offset 0"),
            std::string::npos);
}

TEST(StoredTypes, ABitOffsetIsRefused) {
  const h5::Handle t = int32_altered([](hid_t id) {
    H5Tset_precision(id, 16);
    H5Tset_offset(id, 8);
  });
  const std::vector<char> image = image_with(
      [&](const h5::File& w) { add_dataset(w, t.id(), H5T_NATIVE_INT32, kInts.data(), 3); });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_NE(refusal([&] {
              h5::read_rows<std::int64_t>(f, "/x", 0, 3);
            }).find("of 16 bits at bit offset 8, little-endian, not a standard integer"),
            std::string::npos);
}

TEST(StoredTypes, AnIntegerTheReaderCannotHoldIsRefused) {
  const std::vector<std::int64_t> big = {1, 2, 3};
  const std::vector<std::int32_t> neg = {-1, 0, 1};
  const std::vector<char> image = image_with([&](const h5::File& w) {
    add_dataset(w, H5T_STD_U64LE, H5T_NATIVE_INT64, big.data(), 3, "/u64");
    add_dataset(w, H5T_STD_I8LE, H5T_NATIVE_INT32, neg.data(), 3, "/i8");
    add_dataset(w, H5T_STD_I64LE, H5T_NATIVE_INT64, big.data(), 3, "/i64");
  });
  const h5::File f = h5::open_image(image, "types.h5");
  // sign: an unsigned 64-bit integer does not fit an int64, a signed one not a uint8
  EXPECT_EQ(refusal([&] { h5::read<std::int64_t>(f, "/u64", {3}); }),
            "types.h5: /u64: stored as a 8-byte unsigned integer of 64 bits at bit offset 0, "
            "little-endian, which does not fit the int64 read here (docs/schema.md)");
  EXPECT_NE(refusal([&] { h5::read<std::uint8_t>(f, "/i8", {3}); }).find("does not fit the uint8"),
            std::string::npos);
  // size: an int64 into the int32 of a contact's grain index
  EXPECT_NE(
      refusal([&] { h5::read_rows<std::int32_t>(f, "/i64", 0, 3); }).find("does not fit the int32"),
      std::string::npos);
  EXPECT_EQ(h5::read<double>(f, "/u64", {3}), (std::vector<double>{1, 2, 3}));
}

TEST(StoredTypes, AFloatWithOtherFieldsIsRefused) {
  const std::vector<double> v = {1, 2, 3};
  h5::Handle t(H5Tcopy(H5T_IEEE_F64LE));
  ASSERT_GE(H5Tset_ebias(t.id(), 1000), 0);  // not IEEE's 1023
  const std::vector<char> image = image_with(
      [&](const h5::File& w) { add_dataset(w, t.id(), H5T_NATIVE_DOUBLE, v.data(), 3); });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_NE(refusal([&] { h5::read<double>(f, "/x", {3}); }).find("not a standard integer or IEEE"),
            std::string::npos);
}

TEST(StoredTypes, RankExtentAndANullSpaceAreChecked) {
  const std::vector<double> v = {1, 2, 3, 4, 5, 6};
  const std::vector<char> image = image_with([&](const h5::File& w) {
    const hsize_t dims[2] = {3, 2};
    h5::Handle space(H5Screate_simple(2, dims, nullptr));
    h5::Handle d(H5Dcreate2(w.id(), "/m", H5T_IEEE_F64LE, space.id(), H5P_DEFAULT, H5P_DEFAULT,
                            H5P_DEFAULT));
    H5Dwrite(d.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    h5::Handle null(H5Screate(H5S_NULL));
    h5::Handle e(H5Dcreate2(w.id(), "/null", H5T_IEEE_F64LE, null.id(), H5P_DEFAULT, H5P_DEFAULT,
                            H5P_DEFAULT));
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/m", {h5::any}); }),
            "types.h5: /m: expected shape [*], found [3 x 2]");
  EXPECT_EQ(refusal([&] {
              h5::read<double>(f, "/m", {3, 3});
            }),
            "types.h5: /m: expected shape [3 x 3], found [3 x 2]");
  EXPECT_EQ(h5::read<double>(f, "/m", {h5::any, 2}), v);
  // an extent of 0 is exact: a shape taken from an empty dataset matches no other one
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/m", {0, 2}); }),
            "types.h5: /m: expected shape [0 x 2], found [3 x 2]");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/null", {}); }),
            "types.h5: /null: has no values (a null data space)");
  EXPECT_EQ(refusal([&] { h5::read_rows<double>(f, "/null", 0, 0); }),
            "types.h5: /null: has no values (a null data space)");
}

TEST(StoredTypes, AttributesAreCheckedLikeDatasets) {
  const std::vector<char> image = image_with([](const h5::File& w) {
    h5::create_group(w, "/g");
    h5::Handle g(H5Oopen(w.id(), "/g", H5P_DEFAULT));
    const std::int32_t one = 7;
    h5::Handle scalar(H5Screate(H5S_SCALAR));
    const h5::Handle odd = int32_altered([](hid_t id) { H5Tset_precision(id, 20); });
    h5::Handle a(H5Acreate2(g.id(), "odd", odd.id(), scalar.id(), H5P_DEFAULT, H5P_DEFAULT));
    H5Awrite(a.id(), H5T_NATIVE_INT32, &one);
    h5::Handle b(H5Acreate2(g.id(), "wide", H5T_STD_U64LE, scalar.id(), H5P_DEFAULT, H5P_DEFAULT));
    const std::uint64_t u = 7;
    H5Awrite(b.id(), H5T_NATIVE_UINT64, &u);
    const hsize_t dims[2] = {1, 1};
    h5::Handle square(H5Screate_simple(2, dims, nullptr));
    h5::Handle c(
        H5Acreate2(g.id(), "square", H5T_IEEE_F64LE, square.id(), H5P_DEFAULT, H5P_DEFAULT));
    const double x = 2.5;
    H5Awrite(c.id(), H5T_NATIVE_DOUBLE, &x);
    h5::Handle null(H5Screate(H5S_NULL));
    h5::Handle d(H5Acreate2(g.id(), "none", H5T_IEEE_F64LE, null.id(), H5P_DEFAULT, H5P_DEFAULT));
    h5::set_attr(w, "/g", "ok", 1.5);
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_NE(refusal([&] {
              h5::attr_int(f, "/g", "odd");
            }).find("/g: attribute 'odd': stored as a 4-byte signed integer of 20 bits"),
            std::string::npos);
  EXPECT_EQ(refusal([&] { h5::attr_int(f, "/g", "wide"); }),
            "types.h5: /g: attribute 'wide': stored as a 8-byte unsigned integer of 64 bits at "
            "bit offset 0, little-endian, which does not fit the int64 read here "
            "(docs/schema.md)");
  EXPECT_EQ(refusal([&] { h5::attr_double(f, "/g", "square"); }),
            "types.h5: /g: attribute 'square': has rank 2, expected one value or a list");
  EXPECT_EQ(refusal([&] { h5::attr_double(f, "/g", "none"); }),
            "types.h5: /g: attribute 'none': has no values (a null data space)");
  EXPECT_EQ(h5::attr_double(f, "/g", "ok"), 1.5);
}

// The finding of the issue "Damaged types and structures": a product of the earlier format
// (no checksums) in which a float column became a 4-byte integer of a precision beyond its
// size. The child that rewrites such files copies the type as it is; HDF5's
// integer-to-float conversion in the tool's process then read outside its buffer (SIGBUS).
TEST(StoredTypes, ADamagedTypeInAFileOfTheEarlierFormatIsRefusedNotConverted) {
  // The datatype message of a signed little-endian 4-byte integer (version 1, fixed point):
  // flags, size 4, bit offset 0, precision 32. Its precision becomes 16384 bits.
  const std::vector<char> bytes = earlier_format_with(
      [](const h5::File& w) {
        add_dataset(w, H5T_STD_I32LE, H5T_NATIVE_INT32, kInts.data(), 3, "/theta");
      },
      {0x10, 0x08, 0, 0, 4, 0, 0, 0, 0, 0, 0x20, 0}, {0x10, 0x08, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0x40});
  // By path, as correlate read the file reported.
  const fs::path path =
      fs::temp_directory_path() / ("cdpile-types-" + std::to_string(::getpid()) + ".h5");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const std::string why = refusal([&] {
    const h5::File f = h5::open_read(path.string(), "old.h5");
    h5::read<double>(f, "/theta", {3});
  });
  fs::remove(path);
  EXPECT_EQ(why,
            "old.h5: /theta: stored as a 4-byte signed integer of 16384 bits at bit offset 0, "
            "little-endian, not a standard integer or IEEE float type (damaged, or written by "
            "another program): refused before conversion");
}

// A text attribute is read with its own stored type (HDF5 converts nothing), so what is
// checked is that it is text the schema can store: a class of text, a character set and
// padding HDF5 names, at least one byte. HDF5's API writes no other set or padding; the
// file of the earlier format below is damaged to hold them, as another program could.
TEST(StoredTypes, AttributesOfTextAreTextOfAKnownSetAndPadding) {
  const std::vector<char> image = image_with([](const h5::File& w) {
    h5::set_attr(w, "/", "number", 2.5);
    h5::set_attr(w, "/", "text", std::string("abc"));
    h5::set_attr(w, "/", "list", std::vector<std::string>{"a", "b"});
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::attr_string(f, "/", "number"); }),
            "types.h5: /: attribute 'number' is not text");
  EXPECT_EQ(refusal([&] { h5::attr_double(f, "/", "text"); }),
            "types.h5: /: attribute 'text' is not a number");
  EXPECT_EQ(refusal([&] { h5::attr_int(f, "/", "number"); }),
            "types.h5: /: attribute 'number' should be an integer");
  EXPECT_EQ(refusal([&] { h5::attr_string(f, "/", "list"); }),
            "types.h5: /: attribute 'list' should hold one text");
  EXPECT_EQ(h5::attr_string(f, "/", "text"), "abc");

  // The datatype message of the 4-byte text "abc" (version 1, class string): its flags
  // hold the padding (low 4 bits: 0, NUL-terminated) and the character set (high 4: 1,
  // UTF-8), then its size.
  const std::vector<char> stored = {0x13, 0x10, 0, 0, 4, 0, 0, 0};
  const auto damaged = [&](const std::vector<char>& to) {
    const std::vector<char> bytes = earlier_format_with(
        [](const h5::File& w) { h5::set_attr(w, "/", "author", std::string("abc")); }, stored, to);
    return refusal([&] { h5::attr_string(h5::open_image(bytes, "old.h5"), "/", "author"); });
  };
  EXPECT_EQ(damaged({0x13, 0x20, 0, 0, 4, 0, 0, 0}),
            "old.h5: /: attribute 'author': text of unknown character set (code 2)");
  EXPECT_EQ(damaged({0x13, 0x13, 0, 0, 4, 0, 0, 0}),
            "old.h5: /: attribute 'author': text of unknown padding (code 3)");
}

// An external link names another file: HDF5 would open it and hand its data over as this
// file's. The readers refuse it wherever a path goes through one (found by the structure
// mutator, docs/fuzzing.md).
TEST(StoredStructure, AnExternalLinkIsRefusedNotFollowed) {
  const fs::path other =
      fs::temp_directory_path() / ("cdpile-other-" + std::to_string(::getpid()) + ".h5");
  {
    h5::File o = h5::create(other.string(), "other.h5");
    h5::write(o, "/x", std::vector<double>{1, 2, 3});
  }
  const std::vector<char> image = image_with([&](const h5::File& w) {
    h5::create_group(w, "/g");
    H5Lcreate_external(other.c_str(), "/x", w.id(), "/g/x", H5P_DEFAULT, H5P_DEFAULT);
    H5Lcreate_external(other.c_str(), "/", w.id(), "/outside", H5P_DEFAULT, H5P_DEFAULT);
  });
  const h5::File f = h5::open_image(image, "types.h5");
  const std::string why = refusal([&] { h5::read<double>(f, "/g/x", {3}); });
  const std::string through = refusal([&] { h5::read<double>(f, "/outside/x", {3}); });
  fs::remove(other);
  EXPECT_EQ(why,
            "types.h5: /g/x: a link to another file (external or user-defined link): refused, "
            "the schema keeps every object in its file");
  EXPECT_EQ(through,
            "types.h5: /outside: a link to another file (external or user-defined link): "
            "refused, the schema keeps every object in its file");
}

// Chunks pass through the schema's filters (shuffle, deflate) and Fletcher-32; any other
// filter is refused before a chunk is read: HDF5 1.10.8's scale-offset filter read outside
// its buffer on a file HDF5 wrote (found by the structure mutator, docs/fuzzing.md).
TEST(StoredStructure, OnlyTheSchemasFiltersAndFletcher32AreRead) {
  const std::vector<double> v = {1, 2, 3, 4};
  const std::vector<char> image = image_with([&](const h5::File& w) {
    const hsize_t n = 4, chunk = 2;
    h5::Handle space(H5Screate_simple(1, &n, nullptr));
    auto make = [&](const char* path, auto&& filters) {
      h5::Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
      H5Pset_chunk(dcpl.id(), 1, &chunk);
      filters(dcpl.id());
      h5::Handle d(H5Dcreate2(w.id(), path, H5T_IEEE_F64LE, space.id(), H5P_DEFAULT, dcpl.id(),
                              H5P_DEFAULT));
      H5Dwrite(d.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    };
    make("/checked", [](hid_t p) {
      H5Pset_shuffle(p);
      H5Pset_deflate(p, 4);
      H5Pset_fletcher32(p);
    });
    make("/nbit", [](hid_t p) { H5Pset_nbit(p); });
    make("/scaled", [](hid_t p) { H5Pset_scaleoffset(p, H5Z_SO_FLOAT_DSCALE, 2); });
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(h5::read<double>(f, "/checked", {4}), v);
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/nbit", {4}); }),
            "types.h5: /nbit: stored through the N-bit filter: the readers take chunks through "
            "deflate, shuffle and Fletcher-32 only");
  EXPECT_EQ(refusal([&] { h5::read_rows<double>(f, "/scaled", 0, 2); }),
            "types.h5: /scaled: stored through the scale-offset filter: the readers take chunks "
            "through deflate, shuffle and Fletcher-32 only");
}

// The links the structure mutator breaks: a group where the schema has a dataset and a
// dataset where it has a group, a link removed, a soft link to nothing or to itself. Each
// is refused when the path is opened, before anything under it is read.
TEST(StoredStructure, AnObjectOfTheOtherKindOrNoneIsRefused) {
  const std::vector<char> image = image_with([](const h5::File& w) {
    h5::create_group(w, "/x");
    h5::write(w, "/g", std::vector<double>{1, 2, 3});
    H5Lcreate_soft("/nowhere", w.id(), "/dangling", H5P_DEFAULT, H5P_DEFAULT);
    H5Lcreate_soft("/self", w.id(), "/self", H5P_DEFAULT, H5P_DEFAULT);
  });
  const h5::File f = h5::open_image(image, "types.h5");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/x", {3}); }), "types.h5: /x: not a dataset");
  EXPECT_EQ(refusal([&] { h5::members(f, "/g"); }), "types.h5: /g: not a group");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/y", {3}); }), "types.h5: /y: missing dataset");
  EXPECT_EQ(refusal([&] { h5::members(f, "/y"); }), "types.h5: /y: missing group");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/dangling", {3}); }),
            "types.h5: /dangling: not a dataset");
  EXPECT_EQ(refusal([&] { h5::read<double>(f, "/self", {3}); }), "types.h5: /self: not a dataset");
}
