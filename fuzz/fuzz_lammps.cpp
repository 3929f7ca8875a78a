// libFuzzer harness: the LAMMPS and LIGGGHTS readers of from-lammps (io::lammps:
// parse_script, parse_dump through convert), as the tool reads an input script and its
// dumps. The input is the options byte, then the script and up to three dumps separated by
// NUL bytes (the seeds: fuzz/corpus/lammps/, made by make_corpus.sh from the dumps of
// tests/tools/from-lammps/make_dumps.py). The options byte's bits choose --duplicates
// merge, --check, and --rate 2 --dt 1e-3. An `include` in the script is looked up in a
// folder that does not exist. A cdpile::Error is the expected outcome of a bad input;
// anything else is a finding (docs/fuzzing.md).
#include "cdpile/error.hpp"
#include "cdpile/io/lammps.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace lmp = cdpile::io::lammps;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return -1;
  const std::uint8_t flags = data[0];
  std::vector<std::string> parts(1);
  for (std::size_t k = 1; k < size; ++k) {
    if (data[k] == 0 && parts.size() < 4)
      parts.emplace_back();
    else
      parts.back().push_back(static_cast<char>(data[k]));
  }
  try {
    lmp::ConvertOptions opt;
    lmp::parse_script(parts[0], "fuzz.in", "/nonexistent-cdpile-fuzz", opt.script);
    opt.duplicates = (flags & 1) ? cdpile::io::Duplicates::merge : cdpile::io::Duplicates::error;
    opt.check = (flags & 2) != 0;
    if (flags & 4) {
      opt.rate = 2.0;
      opt.dt = 1e-3;
    }
    std::vector<lmp::TextFile> dumps;
    for (std::size_t k = 1; k < parts.size(); ++k)
      dumps.push_back({"fuzz." + std::to_string(k), parts[k]});
    lmp::convert(dumps, opt);
  } catch (const cdpile::Error&) {
  }
  return 0;
}
