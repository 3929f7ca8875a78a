/// A small, fully specified pile for tests and examples: a row of touching disks on the
/// floor with contact forces that balance their weight, plus a few steps of observables.
#pragma once

#include "cdpile/io/schema.hpp"

namespace cdpile::io {

/// The sample's header and single frame (deterministic for a given seed).
RunHeader sample_header(double diameter);
Frame sample_frame(std::size_t grains, double diameter, std::uint64_t seed);
Series sample_series(std::size_t steps);

/// Writes the sample pile (one frame, `grains` grains, 4 steps of observables) to `f`.
void write_sample_pile(h5::File& f, std::size_t grains, double diameter, std::uint64_t seed,
                       const Provenance& p);

}  // namespace cdpile::io
