// libFuzzer harness: the contact table reader (io::read_contact_table), as localnu reads
// another code's contacts; the first byte chooses how duplicates are treated (refused or
// merged). A cdpile::Error is the expected outcome of a bad table; anything else is a
// finding (docs/fuzzing.md).
#include "cdpile/error.hpp"
#include "cdpile/io/contact_table.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return -1;
  cdpile::io::ContactTableOptions opt;
  opt.duplicates = (data[0] & 1) ? cdpile::io::Duplicates::merge : cdpile::io::Duplicates::error;
  try {
    cdpile::io::read_contact_table(std::string(reinterpret_cast<const char*>(data) + 1, size - 1),
                                   "fuzz", opt);
  } catch (const cdpile::Error&) {
  }
  return 0;
}
