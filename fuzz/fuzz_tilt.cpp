// libFuzzer harness: tilt-cd's start from a pile, as `tilt-cd pile.h5 --to T -o run.h5`
// makes it at the tools' defaults: the pile read (sim::read_pile: the reader and the pile's
// parameters), the engine's settings made from it (sim::pile_settings), and two steps of
// the tilt run and written (sim::run_tilt), which reach the engine's warm start, contact
// detection and solver with every value the file holds. A cdpile::Error (a refused file,
// a state that turns non-finite) is the expected outcome of a damaged pile, as is a
// UsageError from the settings' own checks; anything else is a finding (docs/fuzzing.md).
#include "cdpile/error.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/sim/tilt.hpp"

#include "open_fuzz_image.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace sim = cdpile::sim;

namespace {
/// A scratch folder for the run, made once, removed at exit.
const std::string& output() {
  static const std::string path = [] {
    std::string dir = (std::filesystem::temp_directory_path() / "cdpile-fuzz-tilt.XXXXXX").string();
    if (!mkdtemp(dir.data())) std::abort();
    static const std::string keep = dir;
    std::atexit([] { std::filesystem::remove_all(keep); });
    return dir + "/run.h5";
  }();
  return path;
}

/// The declared options at their defaults, as cli::option_values gives them when none is
/// given.
cdpile::OptionValues default_values() {
  cdpile::OptionValues values;
  for (const cdpile::OptionDeclaration& d : sim::declared_options())
    std::visit(
        [&, &name = d.name](const auto& v) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) values[name] = v;
        },
        d.default_value);
  return values;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<char> bytes(data, data + size);
  if (!cdpile::io::has_hdf5_signature(bytes)) return -1;
  static const cdpile::OptionValues values = default_values();
  try {
    const cdpile::io::h5::File f = cdpile::fuzz::open_fuzz_image(bytes);
    const sim::PileInput pile = sim::read_pile(f);
    sim::TiltOptions o;
    o.settings = sim::pile_settings(pile, values, {}, {});
    sim::set_declared_options(o, values);
    o.to_deg = o.from_deg + 2 * o.rate_deg;  // two steps
    o.frame_every = 1;
    sim::validate(o);
    sim::run_tilt(pile, o, output(), true, cdpile::io::provenance_now("fuzz_tilt", "", ""));
  } catch (const cdpile::Error&) {
  } catch (const cdpile::UsageError&) {
  }
  std::error_code ec;
  std::filesystem::remove(output(), ec);
  std::filesystem::remove(output() + ".partial", ec);
  return 0;
}
