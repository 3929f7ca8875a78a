#include "cdpile/io/h5.hpp"

#include <H5LTpublic.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace cdpile::io::h5 {

namespace {

[[noreturn]] void fail(const File& f, const std::string& path, const std::string& what) {
  throw Error(f.name(), path, what);
}

template <class Fn>
herr_t check(herr_t status, const File& f, const std::string& path, Fn&& what) {
  if (status < 0) fail(f, path, what());
  return status;
}

hid_t checked_id(hid_t id, const File& f, const std::string& path, const std::string& what) {
  if (id < 0) fail(f, path, what);
  return id;
}

/// The system's reason for a failed write (HDF5's file driver leaves errno set), or a
/// guess when there is none.
std::string reason(int err) { return err != 0 ? std::strerror(err) : "disk full?"; }

std::string dims_text(const std::vector<hsize_t>& d) {
  std::string s = "[";
  for (std::size_t k = 0; k < d.size(); ++k) s += (k ? " x " : "") + std::to_string(d[k]);
  return s + "]";
}

/// Opens an object (group or dataset) for attribute access.
Handle open_object(const File& f, const std::string& path) {
  if (!exists(f, path)) fail(f, path, "missing");
  return Handle(checked_id(H5Oopen(f.id(), path.c_str(), H5P_DEFAULT), f, path, "cannot open"));
}

Handle open_dataset(const File& f, const std::string& path) {
  if (!exists(f, path)) fail(f, path, "missing dataset");
  hid_t id = H5Dopen2(f.id(), path.c_str(), H5P_DEFAULT);
  if (id < 0) fail(f, path, "not a dataset");
  return Handle(id);
}

Handle string_type() {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return Handle(t);
}

void write_attr_raw(const File& f, const std::string& path, const std::string& name, hid_t type,
                    const std::vector<hsize_t>& dims, const void* data) {
  Handle obj = open_object(f, path);
  if (H5Aexists(obj.id(), name.c_str()) > 0) H5Adelete(obj.id(), name.c_str());
  Handle space(dims.empty()
                   ? H5Screate(H5S_SCALAR)
                   : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  Handle attr(
      checked_id(H5Acreate2(obj.id(), name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT), f,
                 path, "cannot create attribute " + name));
  // An empty list (the labels of a text column with no rows, no notes) is a valid
  // attribute of shape [0]; H5Awrite refuses its null buffer, and there is nothing to write.
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  if (n == 0) return;
  check(H5Awrite(attr.id(), type, data), f, path, [&] { return "cannot write attribute " + name; });
}

Handle open_attr(const File& f, const std::string& path, const std::string& name) {
  Handle obj = open_object(f, path);
  if (H5Aexists(obj.id(), name.c_str()) <= 0) fail(f, path, "missing attribute '" + name + "'");
  return Handle(checked_id(H5Aopen(obj.id(), name.c_str(), H5P_DEFAULT), f, path,
                           "cannot open attribute " + name));
}

hssize_t attr_points(const Handle& attr) {
  Handle space(H5Aget_space(attr.id()));
  return H5Sget_simple_extent_npoints(space.id());
}

std::string bytes_text(double b) {
  char buf[32];
  if (b >= 1e9)
    std::snprintf(buf, sizeof buf, "%.3g GB", b / 1e9);
  else if (b >= 1e6)
    std::snprintf(buf, sizeof buf, "%.3g MB", b / 1e6);
  else if (b >= 1e3)
    std::snprintf(buf, sizeof buf, "%.3g kB", b / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.0f bytes", b);
  return buf;
}

// The most a compressed chunk can expand: deflate's limit is 1032 to 1.
constexpr double kMaxExpansion = 1100.0;

/// Refuses, before anything is allocated, a dataset or attribute whose extent claims more
/// bytes than the file could hold: `elements` of `element_bytes` each must fit in the
/// file's size, times deflate's largest ratio when `compressed`. A damaged or hostile file
/// claiming 4e8 contacts is then one line, not an allocation of gigabytes.
void check_claim(const File& f, const std::string& path, double elements, double element_bytes,
                 bool compressed) {
  hsize_t file_bytes = 0;
  if (H5Fget_filesize(f.id(), &file_bytes) < 0) fail(f, path, "cannot get the file's size");
  const double claim = elements * element_bytes;
  const double limit = static_cast<double>(file_bytes) * (compressed ? kMaxExpansion : 1.0);
  if (claim > limit) {
    char n[32];
    std::snprintf(n, sizeof n, "%.0f", elements);
    fail(f, path,
         std::string("too large (claims ") + n + " elements, " + bytes_text(claim) +
             ", in a file of " + bytes_text(static_cast<double>(file_bytes)) + ")");
  }
}

/// Whether a dataset's chunks pass through a filter (deflate): its data may then be
/// larger than the file. Also refuses storage or a chunk larger than the file could hold
/// (found by fuzz_run on files of the earlier format).
bool filtered(const File& f, const std::string& path, hid_t dataset, double element_bytes) {
  // What the dataset's index says it stores cannot exceed the file: HDF5 allocates a
  // chunk's stored size to read it, and a damaged index claiming 4 GB made it try.
  check_claim(f, path + " (stored bytes)", static_cast<double>(H5Dget_storage_size(dataset)), 1.0,
              false);
  Handle dcpl(H5Dget_create_plist(dataset));
  if (!dcpl.valid() || H5Pget_layout(dcpl.id()) != H5D_CHUNKED) return false;
  const int filters = H5Pget_nfilters(dcpl.id());
  // The schema's filters are shuffle and deflate; Fletcher-32 is read too (other programs
  // checksum their chunks). HDF5 1.10.8's scale-offset filter read outside its buffer on
  // a file HDF5 itself wrote (a chunk longer than the extent; found by the structure
  // mutator, docs/fuzzing.md), and no file of the schema needs N-bit, scale-offset or SZIP.
  for (int k = 0; k < filters; ++k) {
    unsigned flags = 0;
    std::size_t n = 0;
    const H5Z_filter_t id = H5Pget_filter2(dcpl.id(), static_cast<unsigned>(k), &flags, &n, nullptr,
                                           0, nullptr, nullptr);
    if (id == H5Z_FILTER_DEFLATE || id == H5Z_FILTER_SHUFFLE || id == H5Z_FILTER_FLETCHER32)
      continue;
    const std::string name = id == H5Z_FILTER_SZIP          ? "SZIP"
                             : id == H5Z_FILTER_NBIT        ? "N-bit"
                             : id == H5Z_FILTER_SCALEOFFSET ? "scale-offset"
                                                            : "number " + std::to_string(id);
    fail(f, path,
         "stored through the " + name +
             " filter: the readers take chunks through deflate, shuffle and Fletcher-32 only");
  }
  const bool compressed = filters > 0;
  std::array<hsize_t, H5S_MAX_RANK> chunk{};
  const int rank = H5Pget_chunk(dcpl.id(), H5S_MAX_RANK, chunk.data());
  if (rank < 0) fail(f, path, "cannot read the chunk size");
  double elements = 1;
  for (int k = 0; k < rank; ++k)
    elements *= static_cast<double>(chunk[static_cast<std::size_t>(k)]);
  check_claim(f, path + " (one chunk)", std::max(elements, 1.0), element_bytes, true);
  return compressed;
}

/// A vector of n elements, or an Error naming the file if memory runs out.
template <class T>
std::vector<T> allocate(const File& f, const std::string& path, hsize_t n) {
  try {
    return std::vector<T>(n);
  } catch (const std::bad_alloc&) {
    fail(f, path,
         "too large (" + std::to_string(n) + " elements, " +
             bytes_text(static_cast<double>(n) * sizeof(T)) + "; out of memory)");
  } catch (const std::length_error&) {
    fail(f, path, "too large (" + std::to_string(n) + " elements)");
  }
}

/// A number type as stored, when it is one the schema reads (docs/schema.md, "Types"):
/// HDF5's standard integers (8 to 64 bits, signed or not) and IEEE floats (32 and 64
/// bits), in either byte order.
struct StoredNumber {
  bool real;  ///< an IEEE float; else an integer
  bool is_signed;
  std::size_t bytes;
};

/// H5Tequal compares every property of an atomic type (class, size, precision, bit
/// offset, sign, padding, byte order, the float's fields and bias): a type damaged or
/// written oddly matches none of these, and HDF5 is never asked to convert it. A precision
/// beyond the type's size made its integer-to-float conversion read outside its buffer
/// and die with SIGBUS (docs/fuzzing.md, "Findings").
std::optional<StoredNumber> standard_number(hid_t type) {
  const std::pair<hid_t, StoredNumber> known[] = {
      {H5T_STD_I8LE, {false, true, 1}},   {H5T_STD_I8BE, {false, true, 1}},
      {H5T_STD_U8LE, {false, false, 1}},  {H5T_STD_U8BE, {false, false, 1}},
      {H5T_STD_I16LE, {false, true, 2}},  {H5T_STD_I16BE, {false, true, 2}},
      {H5T_STD_U16LE, {false, false, 2}}, {H5T_STD_U16BE, {false, false, 2}},
      {H5T_STD_I32LE, {false, true, 4}},  {H5T_STD_I32BE, {false, true, 4}},
      {H5T_STD_U32LE, {false, false, 4}}, {H5T_STD_U32BE, {false, false, 4}},
      {H5T_STD_I64LE, {false, true, 8}},  {H5T_STD_I64BE, {false, true, 8}},
      {H5T_STD_U64LE, {false, false, 8}}, {H5T_STD_U64BE, {false, false, 8}},
      {H5T_IEEE_F32LE, {true, true, 4}},  {H5T_IEEE_F32BE, {true, true, 4}},
      {H5T_IEEE_F64LE, {true, true, 8}},  {H5T_IEEE_F64BE, {true, true, 8}},
  };
  // H5Tequal of HDF5 1.10 takes a float of VAX byte order for an IEEE one: the order,
  // precision and offset are checked here too.
  const H5T_order_t order = H5Tget_order(type);
  if ((order != H5T_ORDER_LE && order != H5T_ORDER_BE) || H5Tget_offset(type) != 0 ||
      H5Tget_precision(type) != 8 * H5Tget_size(type))
    return std::nullopt;
  for (const auto& [id, number] : known)
    if (H5Tequal(type, id) > 0 && H5Tget_order(id) == order) return number;
  return std::nullopt;
}

/// What a stored type is, for a message: "a 4-byte signed integer of 64 bits at bit
/// offset 0, little-endian".
std::string type_text(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const char* kind = "type of unknown class";
  switch (cls) {
    case H5T_INTEGER:
      kind = H5Tget_sign(type) == H5T_SGN_NONE ? "unsigned integer" : "signed integer";
      break;
    case H5T_FLOAT: kind = "float"; break;
    case H5T_STRING: kind = "text"; break;
    case H5T_BITFIELD: kind = "bit field"; break;
    case H5T_OPAQUE: kind = "opaque type"; break;
    case H5T_COMPOUND: kind = "compound type"; break;
    case H5T_REFERENCE: kind = "reference"; break;
    case H5T_ENUM: kind = "enumeration"; break;
    case H5T_VLEN: kind = "variable-length sequence"; break;
    case H5T_ARRAY: kind = "array type"; break;
    default: break;
  }
  std::string s = "a " + std::to_string(H5Tget_size(type)) + "-byte " + kind;
  if (cls == H5T_INTEGER || cls == H5T_FLOAT) {
    s += " of " + std::to_string(H5Tget_precision(type)) + " bits at bit offset " +
         std::to_string(H5Tget_offset(type));
    const H5T_order_t order = H5Tget_order(type);
    s += order == H5T_ORDER_LE   ? ", little-endian"
         : order == H5T_ORDER_BE ? ", big-endian"
                                 : ", byte order code " + std::to_string(static_cast<int>(order));
  }
  return s;
}

template <class T>
constexpr const char* schema_type_name() {
  if constexpr (std::is_same_v<T, double>) return "float64";
  if constexpr (std::is_same_v<T, float>) return "float32";
  if constexpr (std::is_same_v<T, std::int64_t>) return "int64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "int32";
  if constexpr (std::is_same_v<T, std::int8_t>) return "int8";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "uint8";
}

/// Whether every value of the stored type survives its conversion to T: floats no wider
/// than T, integers into a float (exact up to 2^53 in a float64: no count of this schema
/// comes near), integers into an integer type whose range holds the stored one.
template <class T>
bool holds(const StoredNumber& s) {
  if constexpr (std::is_floating_point_v<T>) {
    return !s.real || s.bytes <= sizeof(T);
  } else if constexpr (std::is_signed_v<T>) {
    return !s.real && (s.is_signed ? s.bytes <= sizeof(T) : s.bytes < sizeof(T));
  } else {
    return !s.real && !s.is_signed && s.bytes <= sizeof(T);
  }
}

/// Refuses, before HDF5 converts anything, a stored number type that the schema does not
/// name or whose values T cannot hold. `object` names what is read ("" for the dataset at
/// `path`, "attribute 'x'" for one of its attributes).
template <class T>
void check_number_type(const File& f, const std::string& path, const std::string& object,
                       hid_t type) {
  const std::string what = object.empty() ? "" : object + ": ";
  const H5T_class_t cls = H5Tget_class(type);
  if (std::is_floating_point_v<T> ? cls != H5T_INTEGER && cls != H5T_FLOAT : cls != H5T_INTEGER)
    fail(f, path,
         what + "expected " + (std::is_floating_point_v<T> ? "numbers" : "integers") + ", found " +
             type_text(type));
  const auto stored = standard_number(type);
  if (!stored)
    fail(f, path,
         what + "stored as " + type_text(type) +
             ", not a standard integer or IEEE float type (damaged, or written by another "
             "program): refused before conversion");
  if (!holds<T>(*stored))
    fail(f, path,
         what + "stored as " + type_text(type) + ", which does not fit the " +
             schema_type_name<T>() + " read here (docs/schema.md)");
}

/// Refuses a data space that is neither simple nor scalar: a null one holds no values,
/// and no object of the schema has one.
void check_space(const File& f, const std::string& path, const std::string& object, hid_t space) {
  const H5S_class_t cls = H5Sget_simple_extent_type(space);
  if (cls != H5S_SIMPLE && cls != H5S_SCALAR)
    fail(f, path, (object.empty() ? "" : object + ": ") + "has no values (a null data space)");
}

/// An attribute of the schema is one value or a list: a scalar or rank-1 data space.
void check_attr_space(const File& f, const std::string& path, const std::string& name,
                      const Handle& attr) {
  Handle space(H5Aget_space(attr.id()));
  const std::string object = "attribute '" + name + "'";
  check_space(f, path, object, space.id());
  const int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 0 || rank > 1)
    fail(f, path, object + ": has rank " + std::to_string(rank) + ", expected one value or a list");
}

/// Text as the schema stores it: ASCII or UTF-8, of variable length or fixed (at least one
/// byte), padded by NULs or spaces; HDF5 reads it with its own type, converting nothing.
void check_text_type(const File& f, const std::string& path, const std::string& name, hid_t type) {
  const std::string object = "attribute '" + name + "'";
  const H5T_cset_t cset = H5Tget_cset(type);
  if (cset != H5T_CSET_ASCII && cset != H5T_CSET_UTF8)
    fail(f, path,
         object + ": text of unknown character set (code " +
             std::to_string(static_cast<int>(cset)) + ")");
  if (H5Tis_variable_str(type) > 0) return;
  const H5T_str_t pad = H5Tget_strpad(type);
  if (pad != H5T_STR_NULLTERM && pad != H5T_STR_NULLPAD && pad != H5T_STR_SPACEPAD)
    fail(f, path,
         object + ": text of unknown padding (code " + std::to_string(static_cast<int>(pad)) + ")");
  if (H5Tget_size(type) < 1) fail(f, path, object + ": text of no bytes");
}
}  // namespace

void silence_errors() {
  static std::once_flag once;
  std::call_once(once, [] {
    // No library shutdown at exit: after a close that failed (a full disk), HDF5 1.10's
    // atexit handler closes the half-closed file again and crashes in H5F__close_cb,
    // turning the tool's one error line and exit 1 into a SIGSEGV. Every file a tool
    // writes is closed explicitly (Output::commit) before it exits, and read-only files
    // need no flush, so nothing is lost. Must come before the first other HDF5 call.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  });
}

void Handle::reset() noexcept {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE: H5Fclose(id_); break;
    case H5I_GROUP: H5Gclose(id_); break;
    case H5I_DATASET: H5Dclose(id_); break;
    case H5I_DATASPACE: H5Sclose(id_); break;
    case H5I_DATATYPE: H5Tclose(id_); break;
    case H5I_ATTR: H5Aclose(id_); break;
    case H5I_GENPROP_LST: H5Pclose(id_); break;
    default: H5Idec_ref(id_); break;
  }
  id_ = H5I_INVALID_HID;
}

void File::close() {
  if (!h_.valid()) return;
  const hid_t raw = h_.release();
  errno = 0;
  const bool flushed = H5Fflush(raw, H5F_SCOPE_LOCAL) >= 0;
  const int flush_errno = errno;
  const bool closed = H5Fclose(raw) >= 0;
  if (!flushed || !closed)
    throw Error(name_, "", "cannot write the file: " + reason(flushed ? errno : flush_errno));
}

File create(const std::string& path, const std::string& name) {
  silence_errors();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  // The file format of HDF5 1.10 (superblock version 3, version-2 object headers, new-
  // style groups): its metadata carries checksums, so a damaged header is refused as a
  // checksum error instead of being followed into a wild read (docs/fuzzing.md). HDF5
  // 1.10 and later (h5py, ParaView) read it; 1.8 does not.
  H5Pset_libver_bounds(fapl.id(), H5F_LIBVER_V110, H5F_LIBVER_V110);
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE));
  H5Pset_link_creation_order(fcpl.id(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  errno = 0;
  hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id());
  if (id < 0) throw Error(name, "", "cannot create HDF5 file: " + reason(errno));
  return File(Handle(id), name);
}

File create_in_memory(const std::string& name) {
  silence_errors();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_fapl_core(fapl.id(), 1 << 20, 0);  // grow by 1 MiB, no backing store
  // The format of files (create): with its version-3 superblock, H5Fget_file_image of
  // HDF5 1.10 returns an image whose superblock checksum is stale (found by
  // test_io_schema); image_of reseals it.
  H5Pset_libver_bounds(fapl.id(), H5F_LIBVER_V110, H5F_LIBVER_V110);
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE));
  H5Pset_link_creation_order(fcpl.id(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  hid_t id = H5Fcreate(("cdpile-memory-" + name).c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id());
  if (id < 0) throw Error(name, "", "cannot create an in-memory HDF5 file");
  return File(Handle(id), name);
}

File open_read_unchecked(const std::string& path, const std::string& name) {
  silence_errors();
  if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(name, "", "not an HDF5 file, or truncated");
  hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw Error(name, "", "cannot open as HDF5 (truncated or damaged?)");
  return File(Handle(id), name);
}

File open_read(const std::string& path, const std::string& name) {
  silence_errors();
  std::error_code ec;
  const auto bytes = static_cast<double>(std::filesystem::file_size(path, ec));
  const int superblock = superblock_version(path);
  if (superblock == 0 || superblock == 1)
    return open_earlier_format(
        superblock, ec ? 0.0 : bytes, [&] { return open_read_unchecked(path, name); }, name);
  File f = open_read_unchecked(path, name);
  read_string_attributes(f);
  return f;
}

File open_write(const std::string& path, const std::string& name) {
  silence_errors();
  hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (id < 0) throw Error(name, "", "cannot open HDF5 file for writing");
  return File(Handle(id), name);
}

File open_image(const std::vector<char>& bytes, const std::string& name) {
  silence_errors();
  const int superblock = superblock_version(bytes);
  if (superblock == 0 || superblock == 1)
    return open_earlier_format(
        superblock, static_cast<double>(bytes.size()),
        [&] { return open_image_unchecked(bytes, name); }, name);
  File f = open_image_unchecked(bytes, name);
  read_string_attributes(f);
  return f;
}

File open_image_unchecked(const std::vector<char>& bytes, const std::string& name) {
  silence_errors();
  // DONT_COPY|DONT_RELEASE: the caller keeps `bytes` alive while the file is open;
  // read-only, so HDF5 never needs to grow the buffer.
  hid_t id = H5LTopen_file_image(const_cast<char*>(bytes.data()), bytes.size(),
                                 H5LT_FILE_IMAGE_DONT_COPY | H5LT_FILE_IMAGE_DONT_RELEASE);
  if (id < 0) throw Error(name, "", "cannot open the HDF5 data (truncated or damaged?)");
  return File(Handle(id), name);
}

namespace {
/// Bob Jenkins' lookup3 hashlittle (public domain, 2006): the checksum of HDF5's metadata.
std::uint32_t lookup3(const unsigned char* k, std::size_t length, std::uint32_t initval) {
  auto rot = [](std::uint32_t x, int r) { return (x << r) | (x >> (32 - r)); };
  std::uint32_t a, b, c;
  a = b = c = 0xdeadbeef + static_cast<std::uint32_t>(length) + initval;
  while (length > 12) {
    a += k[0] + (std::uint32_t{k[1]} << 8) + (std::uint32_t{k[2]} << 16) +
         (std::uint32_t{k[3]} << 24);
    b += k[4] + (std::uint32_t{k[5]} << 8) + (std::uint32_t{k[6]} << 16) +
         (std::uint32_t{k[7]} << 24);
    c += k[8] + (std::uint32_t{k[9]} << 8) + (std::uint32_t{k[10]} << 16) +
         (std::uint32_t{k[11]} << 24);
    a -= c;
    a ^= rot(c, 4);
    c += b;
    b -= a;
    b ^= rot(a, 6);
    a += c;
    c -= b;
    c ^= rot(b, 8);
    b += a;
    a -= c;
    a ^= rot(c, 16);
    c += b;
    b -= a;
    b ^= rot(a, 19);
    a += c;
    c -= b;
    c ^= rot(b, 4);
    b += a;
    length -= 12;
    k += 12;
  }
  switch (length) {  // the last 1..12 bytes, fall through
    case 12: c += std::uint32_t{k[11]} << 24; [[fallthrough]];
    case 11: c += std::uint32_t{k[10]} << 16; [[fallthrough]];
    case 10: c += std::uint32_t{k[9]} << 8; [[fallthrough]];
    case 9: c += k[8]; [[fallthrough]];
    case 8: b += std::uint32_t{k[7]} << 24; [[fallthrough]];
    case 7: b += std::uint32_t{k[6]} << 16; [[fallthrough]];
    case 6: b += std::uint32_t{k[5]} << 8; [[fallthrough]];
    case 5: b += k[4]; [[fallthrough]];
    case 4: a += std::uint32_t{k[3]} << 24; [[fallthrough]];
    case 3: a += std::uint32_t{k[2]} << 16; [[fallthrough]];
    case 2: a += std::uint32_t{k[1]} << 8; [[fallthrough]];
    case 1: a += k[0]; break;
    case 0: return c;
  }
  c ^= b;
  c -= rot(b, 14);
  a ^= c;
  a -= rot(c, 11);
  b ^= a;
  b -= rot(a, 25);
  c ^= b;
  c -= rot(b, 16);
  a ^= c;
  a -= rot(c, 4);
  b ^= a;
  b -= rot(a, 14);
  c ^= b;
  c -= rot(b, 24);
  return c;
}
}  // namespace

void reseal_superblock(std::vector<char>& image) {
  // HDF5 1.10's H5Fget_file_image writes the end-of-file address into the image's
  // superblock without updating the checksum that versions 2 and 3 carry: the image then
  // fails its own check when opened. Superblock v2/v3: signature (8), version, sizes of
  // offsets and lengths, flags (4), four addresses, then the lookup3 checksum of the
  // bytes before it (HDF5 File Format Specification, "Superblock").
  if (image.size() < 12 || !std::equal(image.begin(), image.begin() + 8, "\x89HDF\r\n\x1a\n"))
    return;
  const auto version = static_cast<unsigned char>(image[8]),
             offsets = static_cast<unsigned char>(image[9]);
  if (version < 2 || version > 3) return;
  const std::size_t at = 12 + 4 * std::size_t{offsets};
  if (image.size() < at + 4) return;
  const std::uint32_t sum = lookup3(reinterpret_cast<const unsigned char*>(image.data()), at, 0);
  for (int b = 0; b < 4; ++b)
    image[at + static_cast<std::size_t>(b)] = static_cast<char>((sum >> (8 * b)) & 0xff);
}

std::vector<char> image_of(const File& f) {
  if (H5Fflush(f.id(), H5F_SCOPE_GLOBAL) < 0) throw Error(f.name(), "", "cannot flush");
  ssize_t size = H5Fget_file_image(f.id(), nullptr, 0);
  if (size < 0) throw Error(f.name(), "", "cannot get the file image");
  std::vector<char> buf(static_cast<std::size_t>(size));
  if (H5Fget_file_image(f.id(), buf.data(), buf.size()) != size)
    throw Error(f.name(), "", "cannot copy the file image");
  reseal_superblock(buf);
  return buf;
}

bool exists(const File& f, const std::string& path) {
  if (path == "/") return true;
  // Check each component, as H5Lexists fails on a missing intermediate group.
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    std::string part = path.substr(0, pos);
    if (H5Lexists(f.id(), part.c_str(), H5P_DEFAULT) <= 0) return false;
    // An external link would have HDF5 open another file, named by this one, and read it
    // as if it were this file's (found by the structure mutator, docs/fuzzing.md).
    H5L_info_t link;
    if (H5Lget_info(f.id(), part.c_str(), &link, H5P_DEFAULT) >= 0 && link.type != H5L_TYPE_HARD &&
        link.type != H5L_TYPE_SOFT)
      throw Error(f.name(), part,
                  "a link to another file (external or user-defined link): refused, the schema "
                  "keeps every object in its file");
    if (pos == std::string::npos) return true;
  }
}

void create_group(const File& f, const std::string& path) {
  if (exists(f, path)) return;
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE));
  H5Pset_link_creation_order(gcpl.id(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  Handle g(checked_id(H5Gcreate2(f.id(), path.c_str(), lcpl.id(), gcpl.id(), H5P_DEFAULT), f, path,
                      "cannot create group"));
}

void hard_link(const File& f, const std::string& target, const std::string& link) {
  check(H5Lcreate_hard(f.id(), target.c_str(), f.id(), link.c_str(), H5P_DEFAULT, H5P_DEFAULT), f,
        link, [&] { return "cannot link to " + target; });
}

void remove(const File& f, const std::string& path) {
  check(H5Ldelete(f.id(), path.c_str(), H5P_DEFAULT), f, path, [] { return "cannot remove"; });
}

void copy(const File& src, const std::string& path, const File& dst) {
  check(H5Ocopy(src.id(), path.c_str(), dst.id(), path.c_str(), H5P_DEFAULT, H5P_DEFAULT), dst,
        path, [&] { return "cannot copy from " + src.name(); });
}

std::vector<std::string> members(const File& f, const std::string& group) {
  if (!exists(f, group)) fail(f, group, "missing group");
  Handle g(H5Gopen2(f.id(), group.c_str(), H5P_DEFAULT));
  if (!g.valid()) fail(f, group, "not a group");
  H5G_info_t info;
  check(H5Gget_info(g.id(), &info), f, group, [] { return "cannot list"; });
  Handle gcpl(H5Gget_create_plist(g.id()));
  unsigned flags = 0;
  H5Pget_link_creation_order(gcpl.id(), &flags);
  H5_index_t index = (flags & H5P_CRT_ORDER_TRACKED) ? H5_INDEX_CRT_ORDER : H5_INDEX_NAME;
  std::vector<std::string> out;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    ssize_t len = H5Lget_name_by_idx(g.id(), ".", index, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(f, group, "cannot list");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Lget_name_by_idx(g.id(), ".", index, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    out.push_back(name);
  }
  return out;
}

std::vector<hsize_t> shape(const File& f, const std::string& path) {
  Handle d = open_dataset(f, path);
  Handle space(H5Dget_space(d.id()));
  int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 0) fail(f, path, "cannot read shape");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  return dims;
}

template <>
hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
hid_t native_type<float>() {
  return H5T_NATIVE_FLOAT;
}
template <>
hid_t native_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}
template <>
hid_t native_type<std::int32_t>() {
  return H5T_NATIVE_INT32;
}
template <>
hid_t native_type<std::int8_t>() {
  return H5T_NATIVE_INT8;
}
template <>
hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}

namespace {
Handle create_dataset(const File& f, const std::string& path, hid_t type,
                      const std::vector<hsize_t>& dims, Layout layout) {
  std::vector<hsize_t> maxdims = dims;
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  if (layout.chunk_rows > 0) {
    maxdims[0] = H5S_UNLIMITED;
    std::vector<hsize_t> chunk = dims;
    chunk[0] = layout.chunk_rows;
    for (std::size_t k = 1; k < chunk.size(); ++k) chunk[k] = std::max<hsize_t>(chunk[k], 1);
    H5Pset_chunk(dcpl.id(), static_cast<int>(chunk.size()), chunk.data());
    if (layout.deflate > 0) {
      H5Pset_shuffle(dcpl.id());
      H5Pset_deflate(dcpl.id(), static_cast<unsigned>(layout.deflate));
    }
  }
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data()));
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  hid_t id = H5Dcreate2(f.id(), path.c_str(), type, space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT);
  return Handle(checked_id(id, f, path, "cannot create dataset"));
}
}  // namespace

template <class T>
void write(const File& f, const std::string& path, const T* data, const std::vector<hsize_t>& dims,
           Layout layout) {
  Handle d = create_dataset(f, path, native_type<T>(), dims, layout);
  hsize_t n = 1;
  for (auto x : dims) n *= x;
  if (n == 0) return;
  check(H5Dwrite(d.id(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data), f, path,
        [] { return "cannot write (disk full?)"; });
}

template <class T>
void append(const File& f, const std::string& path, const T* data, const std::vector<hsize_t>& dims,
            Layout layout) {
  if (!exists(f, path)) {
    std::vector<hsize_t> empty = dims;
    empty[0] = 0;
    create_dataset(f, path, native_type<T>(), empty, layout);
  }
  Handle d = open_dataset(f, path);
  Handle space(H5Dget_space(d.id()));
  int rank = H5Sget_simple_extent_ndims(space.id());
  std::vector<hsize_t> cur(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), cur.data(), nullptr);
  if (cur.size() != dims.size()) fail(f, path, "rank mismatch on append");
  for (std::size_t k = 1; k < dims.size(); ++k)
    if (cur[k] != dims[k])
      fail(f, path, "shape mismatch on append: " + dims_text(cur) + " vs " + dims_text(dims));
  if (dims[0] == 0) return;
  std::vector<hsize_t> next = cur;
  next[0] += dims[0];
  check(H5Dset_extent(d.id(), next.data()), f, path, [] { return "cannot extend"; });
  Handle fspace(H5Dget_space(d.id()));
  std::vector<hsize_t> start(dims.size(), 0);
  start[0] = cur[0];
  H5Sselect_hyperslab(fspace.id(), H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr);
  Handle mspace(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  check(H5Dwrite(d.id(), native_type<T>(), mspace.id(), fspace.id(), H5P_DEFAULT, data), f, path,
        [] { return "cannot write (disk full?)"; });
}

void write_virtual(const File& f, const std::string& path, const std::vector<hsize_t>& dims,
                   const File& src, const std::string& src_name,
                   const std::vector<VirtualBlock>& blocks) {
  if (blocks.empty()) fail(f, path, "a virtual dataset without a source");
  Handle type(H5Dget_type(open_dataset(src, blocks.front().path).id()));
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  // What no block covers (the z component of a 3-vector) reads as zero.
  const std::vector<unsigned char> zero(H5Tget_size(type.id()), 0);
  H5Pset_fill_value(dcpl.id(), type.id(), zero.data());
  Handle vspace(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  for (const VirtualBlock& b : blocks) {
    Handle d = open_dataset(src, b.path);
    Handle sspace(H5Dget_space(d.id()));
    if (H5Sselect_hyperslab(sspace.id(), H5S_SELECT_SET, b.src_start.data(), nullptr,
                            b.src_count.data(), nullptr) < 0 ||
        H5Sselect_hyperslab(vspace.id(), H5S_SELECT_SET, b.dst_start.data(), nullptr,
                            b.dst_count.data(), nullptr) < 0 ||
        H5Pset_virtual(dcpl.id(), vspace.id(), src_name.c_str(), b.path.c_str(), sspace.id()) < 0)
      fail(src, b.path, "cannot map into the virtual dataset " + path);
  }
  H5Sselect_all(vspace.id());
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  Handle id(checked_id(
      H5Dcreate2(f.id(), path.c_str(), type.id(), vspace.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT),
      f, path, "cannot create the virtual dataset"));
}

void truncate_rows(const File& f, const std::string& path, hsize_t rows) {
  Handle d = open_dataset(f, path);
  Handle space(H5Dget_space(d.id()));
  int rank = H5Sget_simple_extent_ndims(space.id());
  // A partial run's rows are along the first dimension; a damaged one may have none.
  if (rank < 1)
    fail(f, path, "expected rows along a first dimension, found " + std::to_string(std::max(rank, 0)) +
                      " dimensions");
  std::vector<hsize_t> cur(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), cur.data(), nullptr);
  if (rows >= cur[0]) return;
  cur[0] = rows;
  check(H5Dset_extent(d.id(), cur.data()), f, path, [] { return "cannot shrink"; });
}

template <class T>
std::vector<T> read(const File& f, const std::string& path, const std::vector<hsize_t>& expect,
                    std::vector<hsize_t>* dims_out) {
  Handle d = open_dataset(f, path);
  Handle type(H5Dget_type(d.id()));
  check_number_type<T>(f, path, "", type.id());
  Handle space(H5Dget_space(d.id()));
  check_space(f, path, "", space.id());
  int rank = H5Sget_simple_extent_ndims(space.id());
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  if (!expect.empty()) {
    bool ok = dims.size() == expect.size();
    for (std::size_t k = 0; ok && k < dims.size(); ++k)
      ok = expect[k] == any || expect[k] == dims[k];
    if (!ok) {
      std::string want = "[";
      for (std::size_t k = 0; k < expect.size(); ++k)
        want +=
            (k ? " x " : "") + (expect[k] == any ? std::string("*") : std::to_string(expect[k]));
      fail(f, path, "expected shape " + want + "], found " + dims_text(dims));
    }
  }
  hsize_t n = 1;
  double elements = 1;
  for (auto x : dims) {
    n *= x;
    elements *= static_cast<double>(x);
  }
  const auto type_bytes = static_cast<double>(H5Tget_size(type.id()));
  check_claim(f, path, elements, type_bytes, filtered(f, path, d.id(), type_bytes));
  std::vector<T> out = allocate<T>(f, path, n);
  if (n > 0)
    check(H5Dread(d.id(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), f, path,
          [] { return "cannot read (truncated file?)"; });
  if constexpr (std::is_floating_point_v<T>) {
    for (std::size_t k = 0; k < out.size(); ++k)
      if (!std::isfinite(out[k]))
        fail(f, path,
             "non-finite value (" + std::string(std::isnan(out[k]) ? "NaN" : "inf") +
                 ") at element " + std::to_string(k));
  }
  if (dims_out) *dims_out = dims;
  return out;
}

template <class T>
std::vector<T> read_rows(const File& f, const std::string& path, hsize_t first, hsize_t count) {
  Handle d = open_dataset(f, path);
  {
    Handle type(H5Dget_type(d.id()));
    check_number_type<T>(f, path, "", type.id());
  }
  Handle space(H5Dget_space(d.id()));
  check_space(f, path, "", space.id());
  int rank = H5Sget_simple_extent_ndims(space.id());
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  if (rank < 1 || first > dims[0] || count > dims[0] - first)
    fail(f, path,
         "rows " + std::to_string(first) + ".." + std::to_string(first + count) + " out of range " +
             dims_text(dims));
  std::vector<hsize_t> start(dims.size(), 0), cnt = dims;
  start[0] = first;
  cnt[0] = count;
  hsize_t n = 1;
  double elements = 1;
  for (auto x : cnt) {
    n *= x;
    elements *= static_cast<double>(x);
  }
  {
    Handle type(H5Dget_type(d.id()));
    const auto type_bytes = static_cast<double>(H5Tget_size(type.id()));
    check_claim(f, path, elements, type_bytes, filtered(f, path, d.id(), type_bytes));
  }
  std::vector<T> out = allocate<T>(f, path, n);
  if (n == 0) return out;
  H5Sselect_hyperslab(space.id(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr);
  Handle mspace(H5Screate_simple(static_cast<int>(cnt.size()), cnt.data(), nullptr));
  check(H5Dread(d.id(), native_type<T>(), mspace.id(), space.id(), H5P_DEFAULT, out.data()), f,
        path, [] { return "cannot read (truncated file?)"; });
  if constexpr (std::is_floating_point_v<T>) {
    for (std::size_t k = 0; k < out.size(); ++k)
      if (!std::isfinite(out[k]))
        fail(f, path,
             "non-finite value (" + std::string(std::isnan(out[k]) ? "NaN" : "inf") +
                 ") at element " + std::to_string(first * (n / count) + k));
  }
  return out;
}

#define CDPILE_H5_INSTANTIATE(T)                                                                  \
  template void write<T>(const File&, const std::string&, const T*, const std::vector<hsize_t>&,  \
                         Layout);                                                                 \
  template void append<T>(const File&, const std::string&, const T*, const std::vector<hsize_t>&, \
                          Layout);                                                                \
  template std::vector<T> read<T>(const File&, const std::string&, const std::vector<hsize_t>&,   \
                                  std::vector<hsize_t>*);                                         \
  template std::vector<T> read_rows<T>(const File&, const std::string&, hsize_t, hsize_t);
CDPILE_H5_INSTANTIATE(double)
CDPILE_H5_INSTANTIATE(float)
CDPILE_H5_INSTANTIATE(std::int64_t)
CDPILE_H5_INSTANTIATE(std::int32_t)
CDPILE_H5_INSTANTIATE(std::int8_t)
CDPILE_H5_INSTANTIATE(std::uint8_t)
#undef CDPILE_H5_INSTANTIATE

// Text attributes are fixed-length strings: their bytes sit in the attribute itself, so a
// reader never follows a global-heap reference, where damaged files made HDF5 1.10 loop
// for ever (docs/fuzzing.md); H5MD 1.1 asks for them too.
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::string& v) {
  set_attr_fixed(f, path, name, v);
}
void set_attr(const File& f, const std::string& path, const std::string& name, double v) {
  write_attr_raw(f, path, name, H5T_NATIVE_DOUBLE, {}, &v);
}
void set_attr(const File& f, const std::string& path, const std::string& name, std::int64_t v) {
  write_attr_raw(f, path, name, H5T_NATIVE_INT64, {}, &v);
}
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<std::int64_t>& v) {
  write_attr_raw(f, path, name, H5T_NATIVE_INT64, {v.size()}, v.data());
}
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<double>& v) {
  write_attr_raw(f, path, name, H5T_NATIVE_DOUBLE, {v.size()}, v.data());
}
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<std::string>& v) {
  set_attr_fixed(f, path, name, v);
}

namespace {
Handle fixed_string_type(std::size_t size) {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, std::max<std::size_t>(size, 1));
  H5Tset_strpad(t, H5T_STR_NULLTERM);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return Handle(t);
}
}  // namespace

void set_attr_fixed(const File& f, const std::string& path, const std::string& name,
                    const std::string& v) {
  Handle t = fixed_string_type(v.size() + 1);
  std::vector<char> buf(v.size() + 1, '\0');
  std::copy(v.begin(), v.end(), buf.begin());
  write_attr_raw(f, path, name, t.id(), {}, buf.data());
}
void set_attr_fixed(const File& f, const std::string& path, const std::string& name,
                    const std::vector<std::string>& v) {
  std::size_t len = 1;
  for (const auto& s : v) len = std::max(len, s.size() + 1);
  Handle t = fixed_string_type(len);
  std::vector<char> buf(len * v.size(), '\0');
  for (std::size_t k = 0; k < v.size(); ++k)
    std::copy(v[k].begin(), v[k].end(), buf.begin() + static_cast<std::ptrdiff_t>(k * len));
  write_attr_raw(f, path, name, t.id(), {v.size()}, buf.data());
}
void set_attr_ascii(const File& f, const std::string& path, const std::string& name,
                    const std::string& v) {
  Handle t(H5Tcopy(H5T_C_S1));
  H5Tset_size(t.id(), H5T_VARIABLE);
  H5Tset_cset(t.id(), H5T_CSET_ASCII);
  const char* p = v.c_str();
  write_attr_raw(f, path, name, t.id(), {}, &p);
}

bool has_attr(const File& f, const std::string& path, const std::string& name) {
  if (!exists(f, path)) return false;
  Handle obj = open_object(f, path);
  return H5Aexists(obj.id(), name.c_str()) > 0;
}

H5T_class_t attr_class(const File& f, const std::string& path, const std::string& name) {
  Handle a = open_attr(f, path, name);
  Handle t(H5Aget_type(a.id()));
  return H5Tget_class(t.id());
}

std::vector<std::string> attr_strings(const File& f, const std::string& path,
                                      const std::string& name) {
  Handle a = open_attr(f, path, name);
  Handle t(H5Aget_type(a.id()));
  if (H5Tget_class(t.id()) != H5T_STRING) fail(f, path, "attribute '" + name + "' is not text");
  check_text_type(f, path, name, t.id());
  check_attr_space(f, path, name, a);
  hssize_t n = attr_points(a);
  std::vector<std::string> out;
  if (n < 0) fail(f, path, "cannot read attribute " + name);
  if (n == 0) return out;  // an empty list: H5Aread refuses a null buffer
  check_claim(f, path, static_cast<double>(n), static_cast<double>(H5Tget_size(t.id())), false);
  if (H5Tis_variable_str(t.id()) > 0 && f.string_attributes()) {
    // Read by a child when the file was opened (read_string_attributes): their global
    // heap is not checksummed, and a damaged one makes HDF5 loop for ever.
    Handle obj = open_object(f, path);
    H5O_info_t info;
    check(H5Oget_info2(obj.id(), &info, H5O_INFO_BASIC), f, path,
          [&] { return "cannot read attribute " + name; });
    const auto it = f.string_attributes()->find({info.addr, name});
    if (it == f.string_attributes()->end())
      fail(f, path,
           "damaged HDF5 file: attribute '" + name +
               "' was not found when the file was opened (global heap of its string attributes)");
    return it->second;
  }
  if (H5Tis_variable_str(t.id()) > 0) {  // a file this process writes, or opened unchecked
    Handle mt = string_type();
    H5Tset_cset(mt.id(), H5Tget_cset(t.id()));  // HDF5 does not convert between ASCII and UTF-8
    std::vector<char*> p(static_cast<std::size_t>(n), nullptr);
    check(H5Aread(a.id(), mt.id(), p.data()), f, path,
          [&] { return "cannot read attribute " + name; });
    for (char* s : p) out.emplace_back(s ? s : "");
    Handle space(H5Aget_space(a.id()));
    H5Dvlen_reclaim(mt.id(), space.id(), H5P_DEFAULT, p.data());
  } else {
    std::size_t len = H5Tget_size(t.id());
    std::vector<char> buf(len * static_cast<std::size_t>(n) + 1, '\0');
    check(H5Aread(a.id(), t.id(), buf.data()), f, path,
          [&] { return "cannot read attribute " + name; });
    for (hssize_t k = 0; k < n; ++k) {
      const char* s = buf.data() + static_cast<std::size_t>(k) * len;
      out.emplace_back(s, strnlen(s, len));
    }
  }
  return out;
}

std::string attr_string(const File& f, const std::string& path, const std::string& name) {
  auto v = attr_strings(f, path, name);
  if (v.size() != 1) fail(f, path, "attribute '" + name + "' should hold one text");
  return v[0];
}

namespace {
template <class T>
std::vector<T> attr_numbers(const File& f, const std::string& path, const std::string& name) {
  Handle a = open_attr(f, path, name);
  Handle t(H5Aget_type(a.id()));
  H5T_class_t cls = H5Tget_class(t.id());
  if (cls != H5T_INTEGER && cls != H5T_FLOAT)
    fail(f, path, "attribute '" + name + "' is not a number");
  if (std::is_integral_v<T> && cls != H5T_INTEGER)
    fail(f, path, "attribute '" + name + "' should be an integer");
  check_number_type<T>(f, path, "attribute '" + name + "'", t.id());
  check_attr_space(f, path, name, a);
  const hssize_t n = attr_points(a);
  if (n < 0) fail(f, path, "cannot read attribute " + name);
  check_claim(f, path, static_cast<double>(n), static_cast<double>(H5Tget_size(t.id())), false);
  std::vector<T> out(static_cast<std::size_t>(n));
  if (out.empty()) return out;  // an empty list: H5Aread refuses a null buffer
  check(H5Aread(a.id(), native_type<T>(), out.data()), f, path,
        [&] { return "cannot read attribute " + name; });
  if constexpr (std::is_floating_point_v<T>)
    for (T x : out)
      if (!std::isfinite(x)) fail(f, path, "attribute '" + name + "' is not finite");
  return out;
}
}  // namespace

double attr_double(const File& f, const std::string& path, const std::string& name) {
  auto v = attr_numbers<double>(f, path, name);
  if (v.size() != 1) fail(f, path, "attribute '" + name + "' should hold one number");
  return v[0];
}
std::int64_t attr_int(const File& f, const std::string& path, const std::string& name) {
  auto v = attr_numbers<std::int64_t>(f, path, name);
  if (v.size() != 1) fail(f, path, "attribute '" + name + "' should hold one integer");
  return v[0];
}
std::vector<std::int64_t> attr_ints(const File& f, const std::string& path,
                                    const std::string& name) {
  return attr_numbers<std::int64_t>(f, path, name);
}

std::vector<std::string> attr_names(const File& f, const std::string& path) {
  Handle obj = open_object(f, path);
  H5O_info_t info;
  check(H5Oget_info2(obj.id(), &info, H5O_INFO_NUM_ATTRS), f, path,
        [] { return "cannot list attributes"; });
  std::vector<std::string> out;
  for (hsize_t k = 0; k < info.num_attrs; ++k) {
    ssize_t len =
        H5Aget_name_by_idx(obj.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(f, path, "cannot list attributes");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Aget_name_by_idx(obj.id(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    out.push_back(name);
  }
  return out;
}

}  // namespace cdpile::io::h5
