/// The order in which a solver visits the contacts, and how a team of threads shares
/// it (docs/method.md, "Threads").
///
/// A Schedule lists positions (indices into the rows, or into a pcg face) in visiting
/// order, cut into blocks that are grouped in colours. The blocks of one colour share no
/// moving body (walls and glued grains are never written by the solvers), so their local
/// solves commute: the threads of a team split a colour's blocks among them, each block
/// visited in order by one thread, with the same result as one thread. Sums over a sweep
/// (the convergence measures, the dot products of pcg) are made per block and added in
/// block order. So a schedule gives the same numbers, bit for bit, on any number of
/// threads. In pair order the schedule is one colour of one block, as NSGS always did;
/// in SweepOrder::strips a block is a vertical strip of the box, and the colours are the
/// even and the odd strips.
#pragma once

#include "cdpile/cd/contact_system.hpp"
#include "cdpile/cd/team.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace cdpile::cd {

/// How a step's sweeps order the contacts (SolverSettings::sweep_order).
enum class SweepOrder {
  pair,  ///< pair order (or the scramble's permutation), one thread
  /// the box cut into vertical strips at least two largest diameters wide: the even strips,
  /// then the odd ones, each strip's contacts in pair order (or the scramble's); any
  /// number of threads
  strips,
};
const char* sweep_order_name(SweepOrder o);
/// The order of a name ("pair", "strips"); throws cdpile::UsageError on another name.
SweepOrder sweep_order_from_name(const std::string& name);

struct Schedule {
  std::vector<std::uint32_t> positions;  ///< in visiting order (forward)
  /// Blocks: block b is positions [block_start[b], block_start[b + 1]).
  std::vector<std::uint32_t> block_start;
  /// Colours: colour c is blocks [colour_start[c], colour_start[c + 1]).
  std::vector<std::uint32_t> colour_start;
  bool coloured = false;  ///< the blocks of a colour may run on several threads at once

  std::size_t size() const { return positions.size(); }
  std::size_t blocks() const { return block_start.empty() ? 0 : block_start.size() - 1; }
  std::size_t colours() const { return colour_start.empty() ? 0 : colour_start.size() - 1; }
};

/// The schedule of a step's rows: `base` (empty: pair order; else a permutation of the
/// rows, the scramble's) as one group for SweepOrder::pair; for SweepOrder::strips, cut
/// by the strips of s.strip, each strip in the base order. A contact belongs to the lower
/// strip of its moving bodies, so a strip's contacts touch it and the next one only, and
/// two strips of one parity share no moving body. A step with a contact whose bodies lie
/// more than one strip apart (a candidate across a whole strip, in a fast flow), or with
/// fewer than two strips, is one group in the base order.
Schedule row_schedule(const ContactSystem& s, SweepOrder order, std::span<const std::uint32_t> base);

/// Runs work(first, last, block) over every block of `s`, in no colour order: for work
/// that reads and writes only its own block's positions (a count, a copy, a gather after
/// a pass). The team's threads take ranges of blocks of about equal numbers of positions.
/// Without a team, for an uncoloured or a small schedule, on the calling thread in block
/// order.
void for_all_blocks(const Schedule& s, Team* team,
                    const std::function<void(std::size_t first, std::size_t last, std::size_t block)>& work);

/// The sub-schedule of the positions for which keep(position) holds, in the same colours
/// and order, renumbered 0, 1, ... in visiting order, into `out`: `kept` receives the
/// original positions (pcg's face of the active contacts). Both are overwritten, their
/// storage reused: a step builds a face every few sweeps. Each block keeps its positions
/// on the team's threads, in place in `out.positions`; the blocks' kept positions are then
/// put one after the other.
template <class Keep>
void sub_schedule(const Schedule& s, Keep keep, Team* team, std::vector<std::uint32_t>& kept,
                  Schedule& out) {
  // The same colours and blocks, each keeping its positions that pass (an emptied block
  // stays, empty: the blocks of a colour are what the threads share).
  out.coloured = s.coloured;
  out.colour_start = s.colour_start;
  out.block_start.assign(s.blocks() + 1, 0);
  out.positions.resize(s.size());
  for_all_blocks(s, team, [&](std::size_t first, std::size_t last, std::size_t b) {
    std::size_t n = first;
    for (std::size_t q = first; q < last; ++q)
      if (keep(s.positions[q])) out.positions[n++] = s.positions[q];
    out.block_start[b + 1] = static_cast<std::uint32_t>(n - first);
  });
  for (std::size_t b = 0; b < s.blocks(); ++b) out.block_start[b + 1] += out.block_start[b];
  kept.resize(out.block_start.back());
  for_all_blocks(s, team, [&](std::size_t first, std::size_t, std::size_t b) {
    const auto from = out.positions.begin() + static_cast<std::ptrdiff_t>(first);
    std::copy(from, from + (out.block_start[b + 1] - out.block_start[b]),
              kept.begin() + out.block_start[b]);
  });
  out.positions.resize(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) out.positions[k] = static_cast<std::uint32_t>(k);
}

/// The strips of a box `width` wide for grains of largest radius `r_max` (SweepOrder::
/// strips): `wanted` (SolverSettings::strips), or as many as fit at least 4 r_max wide
/// if fewer do (all of those if `wanted` is 0); at least 1.
int strip_count(double width, double r_max, int wanted);

/// While alive, the rows of `s` are stored in the visiting order of a coloured `plan`,
/// which then visits them in place (positions 0, 1, ...): a sweep reads them in memory
/// order rather than scattered over the pair order (a strip's contacts are spread over
/// the whole row list). With `bodies_too` the bodies are stored strip by strip as well
/// (in grain order inside a strip, the bodies that do not move last), the rows' bi and bj
/// renumbered: a strip's contacts then touch a few consecutive kilobytes of bodies rather
/// than bodies spread over the whole list. The destructor puts both back, for the stages
/// after the solve. Nothing is computed in another order, so the numbers are the same;
/// a solver that numbers unknowns by body (face_newton.hpp) keeps the bodies as they are.
/// An uncoloured plan is left as it is.
class RowsInScheduleOrder {
 public:
  RowsInScheduleOrder(ContactSystem& s, Schedule& plan, bool bodies_too = false);
  ~RowsInScheduleOrder();
  RowsInScheduleOrder(const RowsInScheduleOrder&) = delete;
  RowsInScheduleOrder& operator=(const RowsInScheduleOrder&) = delete;

 private:
  ContactSystem& s_;
  std::vector<std::uint32_t> row_of_;  // the pair-order row of each position; empty: not moved
  std::vector<std::int32_t> body_of_;  // the grain-order body of each body; empty: not moved
};

/// Runs work(first, last, block) over the blocks of `s`, colour after colour (backward:
/// the last colour first and every block in reverse; `work` visits its positions in
/// reverse itself), the blocks of a coloured schedule's colour shared among the team's
/// threads in fixed ranges, with a barrier between colours. Without a team, or for an
/// uncoloured schedule, everything runs on the calling thread in the same order.
void for_each_block(const Schedule& s, Team* team, bool backward,
                    const std::function<void(std::size_t first, std::size_t last, std::size_t block)>& work);

/// Runs work(first, last) over [0, n) cut into the team's threads' equal ranges
/// (elementwise work whose result does not depend on the cut).
void for_each_range(std::size_t n, Team* team,
                    const std::function<void(std::size_t first, std::size_t last)>& work);

}  // namespace cdpile::cd
