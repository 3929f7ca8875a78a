// libFuzzer harness: the pile and run reader (io::RunReader) on arbitrary bytes, as the
// tools read a file or standard input: open the HDF5 image, read the header, every
// frame's grains and contacts (the first 8 frames), the per-step series, and the
// /checkpoint group of a partial run as `tilt-cd --resume` reads it (io::read_checkpoint). A cdpile::Error
// is the expected outcome of a damaged file; anything else (a crash, a sanitizer report,
// another exception, a hang past -timeout) is a finding (docs/fuzzing.md).
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/schema.hpp"

#include "open_fuzz_image.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

using cdpile::fuzz::open_fuzz_image;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<char> bytes(data, data + size);
  // Without the signature no tool hands the bytes to HDF5 (io::Input reads them as text).
  if (!cdpile::io::has_hdf5_signature(bytes)) return -1;
  try {
    const cdpile::io::h5::File f = open_fuzz_image(bytes);
    const cdpile::io::RunReader r(f);
    for (std::size_t k = 0; k < std::min<std::size_t>(r.frame_count(), 8); ++k) r.frame(k);
    r.series();
    if (cdpile::io::h5::exists(f, cdpile::io::kCheckpointGroup))
      cdpile::io::read_checkpoint(f, r.grain_properties());
  } catch (const cdpile::Error&) {
  }
  return 0;
}
