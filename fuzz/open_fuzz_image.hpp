// How the harnesses that read HDF5 open their input (fuzz_run, fuzz_product).
#pragma once

#include "cdpile/io/h5.hpp"

#include <cstdlib>
#include <string>
#include <vector>

namespace cdpile::fuzz {
/// As the tools open it (io::h5::open_image: a file of the earlier format is rewritten in
/// the checksummed format by a child process, and that is read), or, with
/// CDPILE_FUZZ_UNCHECKED=1 in the environment, in this process only: how the crashes of
/// libhdf5 on that format were found, and how new ones would be (docs/fuzzing.md).
inline io::h5::File open_fuzz_image(const std::vector<char>& bytes) {
  static const bool unchecked = std::getenv("CDPILE_FUZZ_UNCHECKED") != nullptr;
  return unchecked ? io::h5::open_image_unchecked(bytes, "fuzz")
                   : io::h5::open_image(bytes, "fuzz");
}
}  // namespace cdpile::fuzz
