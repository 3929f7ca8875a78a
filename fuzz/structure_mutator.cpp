// libFuzzer custom mutator for the harnesses that read HDF5 (fuzz_run_structure,
// fuzz_product_structure; docs/fuzzing.md, "The structure mutator"). The byte mutator
// rarely gets past the metadata checksums of this version's format: nearly every byte it
// flips in a header is refused by HDF5 itself, so the readers' own checks are seldom
// reached. This mutator writes, through HDF5, a valid and checksummed file with a wrong
// structure: a dataset or attribute of another type (every class, odd precisions, bit
// offsets, sizes and float layouts, both byte orders), data space (scalar, null, other
// rank or extent), layout (contiguous, compact, chunks of any shape, filters), a missing
// or extra link, a group where a dataset should be and back, soft, dangling, cyclic and
// external links, text of every kind; or a value of the right type in the right place
// that no file should hold (three structural mutations in eight: one element of a numeric
// dataset or attribute, or all of a dataset's, set to NaN, an infinity, 1e300, -0, a
// denormal, an integer type's extreme, an id at or past the grain count, the old value
// scaled; docs/schema.md, "Ranges"). One mutation in four is libFuzzer's own byte
// mutation (the raw data the checksums do not cover). Inputs HDF5 cannot open in this
// version's format (the earlier format, damaged bytes) get the byte mutation only: the
// mutator never parses what the tools would parse in a child. The mutation itself runs in
// a forked child (mutate_in_child): HDF5 1.10.8 crashed in some of its calls.
#include "cdpile/io/h5.hpp"

#include <H5LTpublic.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);
// Set by libFuzzer to save a crash file when a sanitizer reports; weak: absent without one.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace h5 = cdpile::io::h5;

namespace {

using Rng = std::mt19937;

std::size_t pick(Rng& rng, std::size_t n) {
  return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
}

/// Every object of the file (groups and datasets, the root left out), by path.
std::vector<std::string> objects_of(hid_t file, H5O_type_t only = H5O_TYPE_UNKNOWN) {
  struct Found {
    std::vector<std::string> paths;
    H5O_type_t only;
  } found{{}, only};
  H5Ovisit(
      file, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        auto* f = static_cast<Found*>(data);
        if (std::strcmp(name, ".") != 0 && (f->only == H5O_TYPE_UNKNOWN || info->type == f->only))
          f->paths.push_back("/" + std::string(name));
        return 0;
      },
      &found);
  return found.paths;
}

std::string parent_of(const std::string& path) {
  const auto k = path.rfind('/');
  return k == 0 ? "/" : path.substr(0, k);
}

/// A stored type of any class the readers may meet, valid for HDF5 but mostly not one the
/// schema names.
h5::Handle random_type(Rng& rng) {
  const hid_t standard[] = {H5T_STD_I8LE,   H5T_STD_U8LE,   H5T_STD_I16BE,  H5T_STD_U16LE,
                            H5T_STD_I32LE,  H5T_STD_U32BE,  H5T_STD_I64LE,  H5T_STD_I64BE,
                            H5T_STD_U64LE,  H5T_IEEE_F32LE, H5T_IEEE_F32BE, H5T_IEEE_F64LE,
                            H5T_IEEE_F64BE, H5T_STD_B8LE,   H5T_STD_B64LE};
  switch (pick(rng, 9)) {
    case 0:
    case 1: return h5::Handle(H5Tcopy(standard[pick(rng, std::size(standard))]));
    case 2: {  // an integer of odd precision, offset or size
      h5::Handle t(H5Tcopy(pick(rng, 2) ? H5T_STD_I32LE : H5T_STD_U64BE));
      if (pick(rng, 2)) H5Tset_size(t.id(), 1 + pick(rng, 16));
      const std::size_t bits = 8 * H5Tget_size(t.id());
      const std::size_t precision = 1 + pick(rng, bits);
      H5Tset_precision(t.id(), precision);
      H5Tset_offset(t.id(), pick(rng, bits - precision + 1));
      return t;
    }
    case 3: {  // a float of other fields or bias
      h5::Handle t(H5Tcopy(H5T_IEEE_F64LE));
      if (pick(rng, 2))
        H5Tset_ebias(t.id(), pick(rng, 2048));
      else
        H5Tset_fields(t.id(), 63, 52 - pick(rng, 8), 11, 0, 52 - pick(rng, 8));
      return t;
    }
    case 4: {  // text, fixed or variable, of either character set and any padding
      h5::Handle t(H5Tcopy(H5T_C_S1));
      H5Tset_size(t.id(), pick(rng, 3) ? 1 + pick(rng, 64) : H5T_VARIABLE);
      H5Tset_cset(t.id(), pick(rng, 2) ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
      const H5T_str_t pads[] = {H5T_STR_NULLTERM, H5T_STR_NULLPAD, H5T_STR_SPACEPAD};
      H5Tset_strpad(t.id(), pads[pick(rng, 3)]);
      return t;
    }
    case 5: {  // a compound of a number, as another program's table might hold
      h5::Handle t(H5Tcreate(H5T_COMPOUND, 16));
      H5Tinsert(t.id(), "x", 0, H5T_NATIVE_DOUBLE);
      H5Tinsert(t.id(), "n", 8, H5T_NATIVE_INT64);
      return t;
    }
    case 6: {  // an enumeration on an integer (h5py's bool)
      h5::Handle t(H5Tenum_create(H5T_NATIVE_INT8));
      const std::int8_t no = 0, yes = 1;
      H5Tenum_insert(t.id(), "FALSE", &no);
      H5Tenum_insert(t.id(), "TRUE", &yes);
      return t;
    }
    case 7: {  // an array of two doubles, or a sequence of them
      const hsize_t two = 2;
      return h5::Handle(pick(rng, 2) ? H5Tarray_create2(H5T_NATIVE_DOUBLE, 1, &two)
                                     : H5Tvlen_create(H5T_NATIVE_DOUBLE));
    }
    default: {
      h5::Handle t(H5Tcreate(H5T_OPAQUE, 1 + pick(rng, 16)));
      H5Tset_tag(t.id(), "cdpile fuzz");
      return t;
    }
  }
}

/// A data space near `dims`: scalar, null, another rank, an extent off by one, zero or
/// doubled.
h5::Handle random_space(Rng& rng, std::vector<hsize_t> dims) {
  switch (pick(rng, 6)) {
    case 0: return h5::Handle(H5Screate(H5S_SCALAR));
    case 1: return h5::Handle(H5Screate(H5S_NULL));
    case 2: dims.push_back(1 + pick(rng, 3)); break;
    case 3:
      if (!dims.empty()) dims.pop_back();
      break;
    default:
      if (dims.empty()) dims.push_back(1);
      {
        hsize_t& d = dims[pick(rng, dims.size())];
        const hsize_t choices[] = {0, d + 1, d > 0 ? d - 1 : 0, 2 * d + 1};
        d = choices[pick(rng, 4)];
      }
  }
  if (dims.empty()) return h5::Handle(H5Screate(H5S_SCALAR));
  return h5::Handle(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
}

std::vector<hsize_t> dims_of(hid_t space) {
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

/// The dataset's values as doubles when HDF5 converts its type, else empty.
std::vector<double> values_of(hid_t dataset) {
  // Not through the N-bit or scale-offset filter: HDF5 1.10.8 reads outside its buffer in
  // scale-offset on chunks longer than the extent (the readers refuse both filters).
  h5::Handle dcpl(H5Dget_create_plist(dataset));
  for (int k = 0; k < H5Pget_nfilters(dcpl.id()); ++k) {
    unsigned flags = 0;
    std::size_t n = 0;
    const H5Z_filter_t id = H5Pget_filter2(dcpl.id(), static_cast<unsigned>(k), &flags, &n, nullptr,
                                           0, nullptr, nullptr);
    if (id == H5Z_FILTER_NBIT || id == H5Z_FILTER_SCALEOFFSET) return {};
  }
  h5::Handle space(H5Dget_space(dataset));
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());
  if (n <= 0 || n > (1 << 22)) return {};
  std::vector<double> v(static_cast<std::size_t>(n));
  if (H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) return {};
  return v;
}

void copy_attributes(hid_t from, hid_t to) {
  H5Aiterate2(
      from, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr,
      [](hid_t obj, const char* name, const H5A_info_t*, void* data) -> herr_t {
        const hid_t dst = *static_cast<hid_t*>(data);
        h5::Handle a(H5Aopen(obj, name, H5P_DEFAULT));
        h5::Handle t(H5Aget_type(a.id())), s(H5Aget_space(a.id()));
        h5::Handle mt(H5Tget_native_type(t.id(), H5T_DIR_DEFAULT));
        const hssize_t n = H5Sget_simple_extent_npoints(s.id());
        if (!mt.valid() || n < 0 || n > (1 << 16)) return 0;
        std::vector<unsigned char> buf(static_cast<std::size_t>(n) * H5Tget_size(mt.id()) + 1);
        if (n > 0 && H5Aread(a.id(), mt.id(), buf.data()) < 0) return 0;
        h5::Handle b(H5Acreate2(dst, name, t.id(), s.id(), H5P_DEFAULT, H5P_DEFAULT));
        if (b.valid() && n > 0) H5Awrite(b.id(), mt.id(), buf.data());
        if (n > 0 && (H5Tdetect_class(mt.id(), H5T_VLEN) > 0 || H5Tis_variable_str(mt.id()) > 0))
          H5Dvlen_reclaim(mt.id(), s.id(), H5P_DEFAULT, buf.data());
        return 0;
      },
      &to);
}

/// Replaces the dataset at `path` by one of type `type`, space `space` and creation
/// properties `dcpl`, holding the old values (converted, cycled to the new size) where
/// HDF5 converts them, and the old attributes.
bool replace_dataset(hid_t file, const std::string& path, hid_t type, hid_t space, hid_t dcpl) {
  h5::Handle old(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!old.valid()) return false;
  const std::vector<double> v = values_of(old.id());
  const std::string tmp = path + ".mutant";
  h5::Handle d(H5Dcreate2(file, tmp.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT));
  if (!d.valid()) return false;
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  if (!v.empty() && n > 0 && n <= (1 << 22) && H5Sget_simple_extent_type(space) != H5S_NULL) {
    std::vector<double> w(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < w.size(); ++k) w[k] = v[k % v.size()];
    H5Dwrite(d.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, w.data());
  }
  copy_attributes(old.id(), d.id());
  old.reset();
  d.reset();
  return H5Ldelete(file, path.c_str(), H5P_DEFAULT) >= 0 &&
         H5Lmove(file, tmp.c_str(), file, path.c_str(), H5P_DEFAULT, H5P_DEFAULT) >= 0;
}

bool retype_dataset(hid_t file, const std::string& path, Rng& rng) {
  h5::Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!d.valid()) return false;
  h5::Handle space(H5Dget_space(d.id())), dcpl(H5Dget_create_plist(d.id()));
  d.reset();
  const h5::Handle type = random_type(rng);
  return replace_dataset(file, path, type.id(), space.id(), dcpl.id());
}

bool reshape_dataset(hid_t file, const std::string& path, Rng& rng) {
  h5::Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!d.valid()) return false;
  h5::Handle type(H5Dget_type(d.id())), space(H5Dget_space(d.id()));
  d.reset();
  const h5::Handle to = random_space(rng, dims_of(space.id()));
  h5::Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  return replace_dataset(file, path, type.id(), to.id(), dcpl.id());
}

/// The same type, extent and values in another layout: contiguous, compact, or chunks of
/// any shape through filters.
bool relayout_dataset(hid_t file, const std::string& path, Rng& rng) {
  h5::Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!d.valid()) return false;
  h5::Handle type(H5Dget_type(d.id())), space(H5Dget_space(d.id()));
  d.reset();
  std::vector<hsize_t> dims = dims_of(space.id());
  h5::Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  h5::Handle to(H5Scopy(space.id()));
  switch (pick(rng, 3)) {
    case 0: break;  // contiguous
    case 1: H5Pset_layout(dcpl.id(), H5D_COMPACT); break;
    default: {
      if (dims.empty()) break;
      std::vector<hsize_t> chunk(dims.size()), maxdims(dims.size(), H5S_UNLIMITED);
      for (std::size_t k = 0; k < dims.size(); ++k) chunk[k] = 1 + pick(rng, dims[k] + 2);
      H5Pset_chunk(dcpl.id(), static_cast<int>(chunk.size()), chunk.data());
      to = h5::Handle(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data()));
      if (pick(rng, 2)) H5Pset_shuffle(dcpl.id());
      if (pick(rng, 2)) H5Pset_deflate(dcpl.id(), static_cast<unsigned>(pick(rng, 10)));
      if (pick(rng, 3) == 0) H5Pset_fletcher32(dcpl.id());
      if (pick(rng, 4) == 0) H5Pset_nbit(dcpl.id());
      if (pick(rng, 4) == 0) H5Pset_scaleoffset(dcpl.id(), H5Z_SO_FLOAT_DSCALE, 2);
    }
  }
  return replace_dataset(file, path, type.id(), to.id(), dcpl.id());
}

/// Writes attribute `name` on `obj` with a random type and space, from a few bytes of
/// text or numbers.
bool write_random_attribute(hid_t obj, const std::string& name, Rng& rng) {
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  h5::Handle space =
      pick(rng, 2) ? h5::Handle(H5Screate(H5S_SCALAR)) : random_space(rng, {1 + pick(rng, 3)});
  const hssize_t n = std::max<hssize_t>(H5Sget_simple_extent_npoints(space.id()), 0);
  if (pick(rng, 2)) {  // text: fixed or variable, long, empty, not UTF-8
    const std::string texts[] = {
        "", "m", "SI", "\xff\xfe not utf-8", std::string(4096, 'x'), "tilt", "1e308", "nan"};
    const std::string& s = texts[pick(rng, std::size(texts))];
    h5::Handle t(H5Tcopy(H5T_C_S1));
    const bool variable = pick(rng, 2);
    H5Tset_size(t.id(), variable ? H5T_VARIABLE : std::max<std::size_t>(s.size(), 1));
    H5Tset_cset(t.id(), pick(rng, 2) ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
    h5::Handle a(H5Acreate2(obj, name.c_str(), t.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT));
    if (!a.valid() || n == 0) return a.valid();
    if (variable) {
      std::vector<const char*> p(static_cast<std::size_t>(n), s.c_str());
      return H5Awrite(a.id(), t.id(), p.data()) >= 0;
    }
    std::vector<char> buf(static_cast<std::size_t>(n) * std::max<std::size_t>(s.size(), 1), ' ');
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k)
      std::copy(s.begin(), s.end(),
                buf.begin() + static_cast<std::ptrdiff_t>(k * std::max<std::size_t>(s.size(), 1)));
    return H5Awrite(a.id(), t.id(), buf.data()) >= 0;
  }
  const double numbers[] = {0, 1, -1, 0.5, 1e308, -1e-308, 4e9, 2.0, 1000};
  const h5::Handle t = random_type(rng);
  h5::Handle a(H5Acreate2(obj, name.c_str(), t.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid() || n == 0) return a.valid();
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) x = numbers[pick(rng, std::size(numbers))];
  H5Awrite(a.id(), H5T_NATIVE_DOUBLE,
           v.data());  // fails (and leaves the fill) where no conversion exists
  return true;
}

/// A random object of the file (the root included), opened, and its number of attributes;
/// an invalid handle where HDF5 cannot open or describe it.
h5::Handle random_object(hid_t file, Rng& rng, hsize_t& attributes) {
  std::vector<std::string> objects = objects_of(file);
  objects.push_back("/");
  const std::string& path = objects[pick(rng, objects.size())];
  h5::Handle obj(H5Oopen(file, path.c_str(), H5P_DEFAULT));
  H5O_info_t info;
  if (!obj.valid() || H5Oget_info2(obj.id(), &info, H5O_INFO_NUM_ATTRS) < 0) return h5::Handle();
  attributes = info.num_attrs;
  return obj;
}

/// Retypes, reshapes, deletes, or adds an attribute of a random object.
bool mutate_attribute(hid_t file, Rng& rng) {
  hsize_t count = 0;
  const h5::Handle obj = random_object(file, rng, count);
  if (!obj.valid()) return false;
  std::string name = "fuzz";
  if (count > 0) {
    char buf[256] = {0};
    const hsize_t k = pick(rng, count);
    if (H5Aget_name_by_idx(obj.id(), ".", H5_INDEX_NAME, H5_ITER_NATIVE, k, buf, sizeof buf,
                           H5P_DEFAULT) < 0)
      return false;
    name = buf;
    if (pick(rng, 4) == 0) return H5Adelete(obj.id(), name.c_str()) >= 0;
  }
  return write_random_attribute(obj.id(), name, rng);
}

/// Removes a link, adds one (hard, soft, dangling, cyclic, external), or puts a group where
/// a dataset was and a dataset where a group was.
bool mutate_links(hid_t file, Rng& rng) {
  const std::vector<std::string> objects = objects_of(file);
  if (objects.empty()) return false;
  const std::string& path = objects[pick(rng, objects.size())];
  const std::string other = objects[pick(rng, objects.size())];
  H5O_info_t info;
  if (H5Oget_info_by_name2(file, path.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0)
    return false;
  switch (pick(rng, 6)) {
    case 0: return H5Ldelete(file, path.c_str(), H5P_DEFAULT) >= 0;
    case 1: {  // the other kind of object in its place
      if (H5Ldelete(file, path.c_str(), H5P_DEFAULT) < 0) return false;
      if (info.type == H5O_TYPE_GROUP) {
        const hsize_t n = 1 + pick(rng, 8);
        h5::Handle space(H5Screate_simple(1, &n, nullptr));
        h5::Handle d(H5Dcreate2(file, path.c_str(), H5T_IEEE_F64LE, space.id(), H5P_DEFAULT,
                                H5P_DEFAULT, H5P_DEFAULT));
        return d.valid();
      }
      h5::Handle g(H5Gcreate2(file, path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
      return g.valid();
    }
    case 2:  // a second name for another object, in its place
      return H5Ldelete(file, path.c_str(), H5P_DEFAULT) >= 0 &&
             H5Lcreate_hard(file, other.c_str(), file, path.c_str(), H5P_DEFAULT, H5P_DEFAULT) >= 0;
    case 3:  // a soft link in its place: to another object, to nothing, to itself
      if (H5Ldelete(file, path.c_str(), H5P_DEFAULT) < 0) return false;
      {
        const std::string targets[] = {other, "/missing", path};
        return H5Lcreate_soft(targets[pick(rng, 3)].c_str(), file, path.c_str(), H5P_DEFAULT,
                              H5P_DEFAULT) >= 0;
      }
    case 4:  // an external link in its place
      if (H5Ldelete(file, path.c_str(), H5P_DEFAULT) < 0) return false;
      return H5Lcreate_external(pick(rng, 2) ? "/dev/zero" : "missing.h5", other.c_str(), file,
                                path.c_str(), H5P_DEFAULT, H5P_DEFAULT) >= 0;
    default:  // an extra member the schema does not name
      return H5Lcreate_hard(file, other.c_str(), file, (parent_of(path) + "/extra").c_str(),
                            H5P_DEFAULT, H5P_DEFAULT) >= 0;
  }
}

/// A number no pile, run or product should hold, or one at the edge of a range
/// (docs/schema.md, "Ranges"): the special floats, the extremes of the integer types, ids
/// at and past the grain count and the walls, and the old value scaled, negated, nudged.
double special_float(Rng& rng, double old) {
  const double values[] = {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           1e300,
                           -1e300,
                           std::numeric_limits<double>::max(),
                           -0.0,
                           0.0,
                           5e-324,                   // the smallest denormal
                           2.2250738585072014e-308,  // the smallest normal
                           -1.0,
                           1.0,
                           90.0,
                           -90.0,
                           90.00000000000001,
                           9007199254740993.0,  // 2^53 + 1 (rounds to 2^53 + 2)
                           9.3e18,              // past INT64_MAX
                           old * 1e6,
                           old * 1e-6,
                           -old,
                           std::nextafter(old, std::numeric_limits<double>::infinity()),
                           old + 1.0};
  return values[pick(rng, std::size(values))];
}

std::int64_t special_integer(Rng& rng, std::int64_t old, std::int64_t grains) {
  const std::int64_t values[] = {std::numeric_limits<std::int64_t>::max(),
                                 std::numeric_limits<std::int64_t>::min(),
                                 std::numeric_limits<std::int32_t>::max(),
                                 std::numeric_limits<std::int32_t>::min(),
                                 std::int64_t{1} << 31,
                                 (std::int64_t{1} << 53) + 1,
                                 -1,
                                 0,
                                 1,
                                 2,
                                 3,
                                 255,
                                 -3,  // the right wall
                                 -4,  // below the walls
                                 grains,
                                 grains - 1,
                                 grains + 1,
                                 old + 1,
                                 old - 1,
                                 -old,
                                 old * 1000};
  return values[pick(rng, std::size(values))];
}

/// The number of grains, if the file has them: ids at and past it are the ones to try.
std::int64_t grain_count(hid_t file) {
  if (H5Lexists(file, "/particles", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "/particles/grains", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "/particles/grains/radius", H5P_DEFAULT) <= 0)
    return 12;
  h5::Handle d(H5Dopen2(file, "/particles/grains/radius", H5P_DEFAULT));
  if (!d.valid()) return 12;
  h5::Handle space(H5Dget_space(d.id()));
  return std::max<hssize_t>(H5Sget_simple_extent_npoints(space.id()), 0);
}

/// One value of a numeric dataset changed, its type, shape and layout kept (or, one time
/// in eight, every value of it): what the checks of docs/schema.md, "Ranges", are for.
bool mutate_dataset_value(hid_t file, const std::string& path, Rng& rng) {
  h5::Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!d.valid()) return false;
  h5::Handle type(H5Dget_type(d.id())), space(H5Dget_space(d.id()));
  const H5T_class_t cls = H5Tget_class(type.id());
  if (cls != H5T_INTEGER && cls != H5T_FLOAT) return false;
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());
  if (n <= 0 || n > (1 << 22) || H5Sget_simple_extent_type(space.id()) != H5S_SIMPLE) return false;
  const std::vector<hsize_t> dims = dims_of(space.id());
  const bool all = pick(rng, 8) == 0;
  hsize_t flat = pick(rng, static_cast<std::size_t>(n));
  std::vector<hsize_t> at(dims.size());
  for (std::size_t k = dims.size(); k-- > 0;) {
    at[k] = flat % dims[k];
    flat /= dims[k];
  }
  const hsize_t one = 1;
  h5::Handle memory(H5Screate_simple(1, &one, nullptr));
  if (!all && H5Sselect_elements(space.id(), H5S_SELECT_SET, 1, at.data()) < 0) return false;
  const hid_t file_space = all ? H5S_ALL : space.id();
  if (cls == H5T_FLOAT) {
    double old = 0;
    if (!all) H5Dread(d.id(), H5T_NATIVE_DOUBLE, memory.id(), file_space, H5P_DEFAULT, &old);
    const double v = special_float(rng, std::isfinite(old) ? old : 1.0);
    if (!all)
      return H5Dwrite(d.id(), H5T_NATIVE_DOUBLE, memory.id(), file_space, H5P_DEFAULT, &v) >= 0;
    const std::vector<double> w(static_cast<std::size_t>(n), v);
    return H5Dwrite(d.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, w.data()) >= 0;
  }
  std::int64_t old = 0;
  if (!all) H5Dread(d.id(), H5T_NATIVE_INT64, memory.id(), file_space, H5P_DEFAULT, &old);
  const std::int64_t v = special_integer(rng, old, grain_count(file));
  if (!all)
    return H5Dwrite(d.id(), H5T_NATIVE_INT64, memory.id(), file_space, H5P_DEFAULT, &v) >= 0;
  const std::vector<std::int64_t> w(static_cast<std::size_t>(n), v);
  return H5Dwrite(d.id(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, w.data()) >= 0;
}

/// One value of a numeric attribute (a parameter, a result, a checkpoint's counter, the
/// schema version) changed, its type and shape kept.
bool mutate_attribute_value(hid_t file, Rng& rng) {
  hsize_t count = 0;
  const h5::Handle obj = random_object(file, rng, count);
  if (!obj.valid() || count == 0) return false;
  h5::Handle a(H5Aopen_by_idx(obj.id(), ".", H5_INDEX_NAME, H5_ITER_NATIVE, pick(rng, count),
                              H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid()) return false;
  h5::Handle type(H5Aget_type(a.id())), space(H5Aget_space(a.id()));
  const H5T_class_t cls = H5Tget_class(type.id());
  const hssize_t n = H5Sget_simple_extent_npoints(space.id());
  if ((cls != H5T_INTEGER && cls != H5T_FLOAT) || n <= 0 || n > (1 << 16)) return false;
  const std::size_t k = pick(rng, static_cast<std::size_t>(n));
  if (cls == H5T_FLOAT) {
    std::vector<double> v(static_cast<std::size_t>(n));
    if (H5Aread(a.id(), H5T_NATIVE_DOUBLE, v.data()) < 0) return false;
    v[k] = special_float(rng, std::isfinite(v[k]) ? v[k] : 1.0);
    return H5Awrite(a.id(), H5T_NATIVE_DOUBLE, v.data()) >= 0;
  }
  std::vector<std::int64_t> v(static_cast<std::size_t>(n));
  if (H5Aread(a.id(), H5T_NATIVE_INT64, v.data()) < 0) return false;
  v[k] = special_integer(rng, v[k], grain_count(file));
  return H5Awrite(a.id(), H5T_NATIVE_INT64, v.data()) >= 0;
}

/// One structural mutation of an image of this version's format, or false (the caller
/// then mutates bytes).
bool mutate_structure(const std::vector<char>& in, Rng& rng, std::vector<char>& out) {
  const int superblock = h5::superblock_version(in);
  if (superblock < 2) return false;  // the earlier format, or no HDF5 signature
  std::vector<char> copy = in;
  const hid_t id = H5LTopen_file_image(copy.data(), copy.size(), H5LT_FILE_IMAGE_OPEN_RW);
  if (id < 0) return false;
  h5::File f(h5::Handle(id), "mutant");
  bool done = false;
  const std::vector<std::string> datasets = objects_of(f.id(), H5O_TYPE_DATASET);
  // Kinds 0 to 4 change the structure, 5 to 7 the values (docs/fuzzing.md, "The value
  // mutations"): a dataset's element twice as often as an attribute's.
  const std::size_t kind = pick(rng, 8);
  if (kind >= 5) {
    if (kind < 7 && !datasets.empty())
      done = mutate_dataset_value(f.id(), datasets[pick(rng, datasets.size())], rng);
    else
      done = mutate_attribute_value(f.id(), rng);
  } else if (kind < 3 && !datasets.empty()) {
    const std::string& path = datasets[pick(rng, datasets.size())];
    done = kind == 0   ? retype_dataset(f.id(), path, rng)
           : kind == 1 ? reshape_dataset(f.id(), path, rng)
                       : relayout_dataset(f.id(), path, rng);
  } else if (kind == 3) {
    done = mutate_attribute(f.id(), rng);
  } else {
    done = mutate_links(f.id(), rng);
  }
  if (!done) return false;
  try {
    out = h5::image_of(f);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

/// The mutation, in a forked child: HDF5 1.10.8 crashed in the mutator's own calls (in
/// H5Ocopy, and freeing an attribute in H5Ldelete of a dataset it had written), and a
/// crash there is no finding of the readers'. The child writes the new image to a pipe;
/// false if it fails or dies.
bool mutate_in_child(const std::vector<char>& in, unsigned seed, std::vector<char>& out) {
  int fds[2];
  if (pipe(fds) != 0) return false;
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return false;
  }
  if (pid == 0) {  // the child: no sanitizer report, no libFuzzer crash file, nothing printed
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
    for (int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDERR_FILENO);
    close(fds[0]);
    Rng rng(seed);
    std::vector<char> image;
    if (!mutate_structure(in, rng, image)) _exit(1);
    std::size_t done = 0;
    while (done < image.size()) {
      const ssize_t n = write(fds[1], image.data() + done, image.size() - done);
      if (n <= 0) _exit(1);
      done += static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  out.clear();
  char buf[65536];
  ssize_t n;
  while ((n = read(fds[0], buf, sizeof buf)) > 0) out.insert(out.end(), buf, buf + n);
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 && !out.empty();
}

}  // namespace

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  Rng rng(seed);
  if (pick(rng, 4) == 0) return LLVMFuzzerMutate(data, size, max_size);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::vector<char> out;
  if (!mutate_in_child(std::vector<char>(data, data + size), static_cast<unsigned>(rng()), out) ||
      out.size() > max_size)
    return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}
