/// A thin RAII layer over the HDF5 C API: handles that close themselves, typed reads
/// and writes of datasets and attributes, and errors that name the file and the path
/// inside it instead of printing HDF5's error stack.
#pragma once

#include "cdpile/error.hpp"

#include <hdf5.h>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace cdpile::io::h5 {

/// Turns off HDF5's automatic error-stack printing and its shutdown at exit (once per
/// process, before any other HDF5 call: cli::run_tool calls it first; see h5.cpp).
void silence_errors();

/// An owned HDF5 identifier, closed with the right H5*close on destruction.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset() noexcept;
  /// Gives up ownership without closing.
  hid_t release() noexcept {
    hid_t x = id_;
    id_ = H5I_INVALID_HID;
    return x;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

/// An open file, remembering the name used in messages.
class File {
 public:
  File() = default;
  /// `image`: the file image the file is opened from, kept alive while it is open.
  File(Handle h, std::string name, std::shared_ptr<const std::vector<char>> image = nullptr)
      : h_(std::move(h)), name_(std::move(name)), image_(std::move(image)) {}
  /// `f`, keeping alive the image it is opened from.
  File(File&& f, std::shared_ptr<const std::vector<char>> image)
      : h_(std::move(f.h_)), name_(std::move(f.name_)), image_(std::move(image)) {}
  ~File() { h_.reset(); }  // the file closes before its image goes
  File(File&&) = default;
  File& operator=(File&&) = default;  // h_ first: the old file closes before its image goes
  hid_t id() const { return h_.id(); }
  bool valid() const { return h_.valid(); }
  const std::string& name() const { return name_; }
  void close();  ///< closes now and reports a failure (a plain destruction does not)
  /// The values of the file's variable-length string attributes, by the address of their
  /// object's header and their name, as a child process read them (open_read, open_image:
  /// read_string_attributes); null for a file whose attributes are read in process (one
  /// this process creates or writes, or opened unchecked).
  using StringAttributes = std::map<std::pair<haddr_t, std::string>, std::vector<std::string>>;
  const StringAttributes* string_attributes() const { return strings_.get(); }
  void set_string_attributes(std::shared_ptr<const StringAttributes> s) { strings_ = std::move(s); }

 private:
  Handle h_;
  std::string name_;
  std::shared_ptr<const std::vector<char>> image_;
  std::shared_ptr<const StringAttributes> strings_;
};

File create(const std::string& path, const std::string& name);  ///< truncate
File create_in_memory(const std::string& name);                 ///< core driver, no backing store
/// Opens a file (open_read) or a file image (open_image) to read. A file of the earlier
/// format, whose superblock has no checksum (version 0 or 1), is not read in this process:
/// open_earlier_format rewrites it in a child process, and the file returned is the
/// rewritten image.
File open_read(const std::string& path, const std::string& name);
File open_write(const std::string& path, const std::string& name);  ///< read-write
File open_image(const std::vector<char>& bytes, const std::string& name);
/// open_read and open_image whatever the format: for the child that rewrites a file of the
/// earlier format, and for the fuzz harnesses' in-process mode.
File open_read_unchecked(const std::string& path, const std::string& name);
File open_image_unchecked(const std::vector<char>& bytes, const std::string& name);
std::vector<char> image_of(const File& f);  ///< flushes and copies the file image
/// Rewrites the checksum of a version-2 or -3 superblock at the start of a file image
/// (image_of calls it: HDF5 1.10 leaves it stale).
void reseal_superblock(std::vector<char>& image);

/// The version of the superblock HDF5 will read: the byte after the first signature at
/// offset 0, 512, 1024, 2048, ... (HDF5 File Format Specification, "Superblock"); -1 when
/// there is no signature. Versions 0 and 1 carry no checksum, and neither does any of
/// the metadata of files of that format.
int superblock_version(const std::vector<char>& image);
int superblock_version(const std::string& path);

/// The file `src` written anew in memory in this version's format (checksummed
/// metadata): the root's attributes copied, every member of the root copied by H5Ocopy
/// (which decodes every header, attribute and chunk index it copies, and writes them
/// anew). Errors name the file and the object.
std::vector<char> rewrite_in_current_format(const File& src);

/// How a child process of run_checked ended.
enum class Check { passed, failed, crashed, looped };
struct Checked {
  Check verdict = Check::crashed;
  std::vector<char> bytes;  ///< what the work returned (passed)
  std::string error;        ///< the Error it threw (failed)
};
/// Runs `work` in a forked child process with its CPU time bounded by `cpu_seconds` and
/// its address space by `memory_bytes` above what the process maps now (not under
/// AddressSanitizer, whose shadow memory is larger than any bound), its stdout and stderr
/// discarded, and brings back its bytes through a pipe: `passed`, `failed` (it threw an
/// Error, or ran out of memory within the bound), `crashed` (it died by a signal or a
/// sanitizer's report) or `looped` (it ran out of CPU time).
Checked run_checked(const std::function<std::vector<char>()>& work, double cpu_seconds,
                    double memory_bytes);
/// A file of HDF5's earlier format (superblock `superblock` 0 or 1, `bytes` long, opened
/// by `open`) rewritten by rewrite_in_current_format in a child process (run_checked,
/// 5 s of CPU time plus 1 s per 8 MB, 1 GB of memory plus 3 times the file), opened from
/// the rewritten image. If the child crashes or loops, an Error naming the file that says
/// so and how to rewrite an intact copy; if rewriting failed, its Error.
File open_earlier_format(int superblock, double bytes, const std::function<File()>& open,
                         const std::string& name);
/// Lists and reads every variable-length string attribute of `f` (a file of this
/// version's format) in a child process (run_checked, 5 s of CPU time) and keeps their
/// values in `f`, where attr_strings finds them: HDF5 1.10 keeps those strings in a global
/// heap, which carries no checksum, and loops for ever on some damaged ones
/// (docs/fuzzing.md). If the child crashes, loops or fails, an Error naming the file
/// ("damaged HDF5 file: ... (global heap of its string attributes)").
void read_string_attributes(File& f);

bool exists(const File& f, const std::string& path);        ///< a link at this absolute path
void create_group(const File& f, const std::string& path);  ///< creates parents too
void hard_link(const File& f, const std::string& target, const std::string& link);
/// Removes the link at `path` (a group or dataset; its space is not reclaimed).
void remove(const File& f, const std::string& path);
/// Copies the object at `path` of `src` to the same path of `dst`, keeping its chunking,
/// filters and the hard links inside a copied group.
void copy(const File& src, const std::string& path, const File& dst);
/// Names of the members of a group, in creation (or name) order.
std::vector<std::string> members(const File& f, const std::string& group);

/// Dataset shape, or error naming the path.
std::vector<hsize_t> shape(const File& f, const std::string& path);

/// Compression and chunking of a dataset. `chunk_rows` 0 = contiguous, fixed size.
struct Layout {
  hsize_t chunk_rows = 0;  ///< rows (first dimension) per chunk; extendible if > 0
  int deflate = 0;         ///< 0 = none, 1..9 gzip level (with the shuffle filter)
};

template <class T>
hid_t native_type();

/// Writes a dataset of shape rows x cols... (`dims`), creating it.
template <class T>
void write(const File& f, const std::string& path, const T* data, const std::vector<hsize_t>& dims,
           Layout layout = {});
template <class T>
void write(const File& f, const std::string& path, const std::vector<T>& v, Layout layout = {}) {
  write(f, path, v.data(), {static_cast<hsize_t>(v.size())}, layout);
}
/// Appends rows to an extendible dataset (first dimension); creates it if absent with
/// the given layout and the trailing dimensions of `dims` (dims[0] = rows appended).
template <class T>
void append(const File& f, const std::string& path, const T* data, const std::vector<hsize_t>& dims,
            Layout layout);
/// One block of a virtual dataset: `count` elements of the source dataset `path` (in the
/// file given to write_virtual) from `src_start`, placed at `dst_start` (blocks of the same
/// shape; a source of higher rank gives its trailing dimensions).
struct VirtualBlock {
  std::string path;
  std::vector<hsize_t> src_start, src_count, dst_start, dst_count;
};
/// Creates a virtual dataset (HDF5 1.10 VDS) of shape `dims` in `f` whose blocks are read
/// from `src` when the dataset is read, never copied: `src_name` is the source file's name
/// as stored (relative names are looked for beside `f`). Elements no block covers read as
/// 0. The type is the first block's source dataset's.
void write_virtual(const File& f, const std::string& path, const std::vector<hsize_t>& dims,
                   const File& src, const std::string& src_name,
                   const std::vector<VirtualBlock>& blocks);
/// Shrinks an extendible dataset to `rows` along its first dimension.
void truncate_rows(const File& f, const std::string& path, hsize_t rows);

/// In an expected shape: any extent. An extent of 0 is exact (an empty dataset): with 0 as
/// the wildcard, a shape computed from an empty dataset matched every other one (found by
/// the structure mutator, docs/fuzzing.md).
inline constexpr hsize_t any = std::numeric_limits<hsize_t>::max();

/// Reads a whole dataset, checking its rank and each dimension given (`expect`, an `any`
/// entry matches every extent). Returns the data flattened in C order.
template <class T>
std::vector<T> read(const File& f, const std::string& path, const std::vector<hsize_t>& expect,
                    std::vector<hsize_t>* dims_out = nullptr);
/// Reads rows [first, first+count) of a dataset along its first dimension.
template <class T>
std::vector<T> read_rows(const File& f, const std::string& path, hsize_t first, hsize_t count);

// Attributes on an object (group or dataset) at `path`.
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::string& v);
void set_attr(const File& f, const std::string& path, const std::string& name, double v);
void set_attr(const File& f, const std::string& path, const std::string& name, std::int64_t v);
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<std::int64_t>& v);
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<double>& v);
void set_attr(const File& f, const std::string& path, const std::string& name,
              const std::vector<std::string>& v);
/// Fixed-length string attributes (UTF-8, null-terminated, sized to the longest text):
/// H5MD 1.1 asks for them in /h5md/author, /h5md/creator and box/boundary.
void set_attr_fixed(const File& f, const std::string& path, const std::string& name,
                    const std::string& v);
void set_attr_fixed(const File& f, const std::string& path, const std::string& name,
                    const std::vector<std::string>& v);
/// A variable-length ASCII string attribute: the H5MD units module's `unit` and `system`.
void set_attr_ascii(const File& f, const std::string& path, const std::string& name,
                    const std::string& v);
bool has_attr(const File& f, const std::string& path, const std::string& name);
/// Class of an attribute: H5T_INTEGER, H5T_FLOAT or H5T_STRING.
H5T_class_t attr_class(const File& f, const std::string& path, const std::string& name);
std::string attr_string(const File& f, const std::string& path, const std::string& name);
double attr_double(const File& f, const std::string& path, const std::string& name);
std::int64_t attr_int(const File& f, const std::string& path, const std::string& name);
std::vector<std::int64_t> attr_ints(const File& f, const std::string& path,
                                    const std::string& name);
std::vector<std::string> attr_strings(const File& f, const std::string& path,
                                      const std::string& name);
std::vector<std::string> attr_names(const File& f, const std::string& path);

}  // namespace cdpile::io::h5
