// libFuzzer harness: the analysis products' reader (io::read_product_hdf5 for bytes with
// the HDF5 signature, io::read_product_tsv for any other text), as correlate and
// clusterfit read their inputs. A cdpile::Error is the expected outcome of a damaged
// file; anything else is a finding (docs/fuzzing.md).
#include "cdpile/io/files.hpp"
#include "cdpile/io/products.hpp"

#include "open_fuzz_image.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

using cdpile::fuzz::open_fuzz_image;

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
