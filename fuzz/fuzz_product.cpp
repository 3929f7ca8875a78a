// libFuzzer harness: the analysis products' reader (io::read_product_hdf5 for bytes with
// the HDF5 signature, io::read_product_tsv for any other text), as correlate and
// clusterfit read their inputs. A cdpile::Error is the expected outcome of a damaged
// file; anything else is a finding (docs/fuzzing.md).
#include "cdpile/io/files.hpp"
#include "cdpile/io/products.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace {
/// As the tools open it (io::h5::open_image: a file of the earlier format is rewritten in
/// the checksummed format by a child process, and that is read), or, with CDPILE_FUZZ_UNCHECKED=1
/// in the environment, in this process only: how the crashes of libhdf5 on that format were found,
/// and how new ones would be (docs/fuzzing.md).
cdpile::io::h5::File open_fuzz_image(const std::vector<char>& bytes) {
  static const bool unchecked = std::getenv("CDPILE_FUZZ_UNCHECKED") != nullptr;
  return unchecked ? cdpile::io::h5::open_image_unchecked(bytes, "fuzz")
                   : cdpile::io::h5::open_image(bytes, "fuzz");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<char> bytes(data, data + size);
  try {
    if (cdpile::io::has_hdf5_signature(bytes)) {
      const cdpile::io::h5::File f = open_fuzz_image(bytes);
      cdpile::io::read_product_hdf5(f);
    } else {
      cdpile::io::read_product_tsv(std::string(bytes.begin(), bytes.end()), "fuzz");
    }
  } catch (const cdpile::Error&) {
  }
  return 0;
}
