// Sweep schedules: pair order, or the strips that threads share (schedule.hpp).
#include "cdpile/cd/schedule.hpp"

#include "cdpile/check.hpp"
#include "cdpile/error.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <string>

namespace cdpile::cd {

const char* sweep_order_name(SweepOrder o) {
  switch (o) {
    case SweepOrder::pair: return "pair";
    case SweepOrder::strips: return "strips";
  }
  return "?";
}

SweepOrder sweep_order_from_name(const std::string& name) {
  for (const SweepOrder o : {SweepOrder::pair, SweepOrder::strips})
    if (name == sweep_order_name(o)) return o;
  throw UsageError("unknown sweep order '" + name + "' (pair or strips)");
}

int strip_count(double width, double r_max, int wanted) {
  if (!(r_max > 0.0) || !(width > 0.0)) return 1;
  const int fit = std::max(1, static_cast<int>(std::min(1e6, std::floor(width / (4.0 * r_max)))));
  return wanted > 0 ? std::min(wanted, fit) : fit;
}

namespace {

// One group, one block: the base order (or pair order), visited by one thread.
Schedule one_group(std::span<const std::uint32_t> base, std::size_t m) {
  Schedule out;
  out.positions.resize(m);
  for (std::size_t q = 0; q < m; ++q)
    out.positions[q] = base.empty() ? static_cast<std::uint32_t>(q) : base[q];
  out.block_start = {0, static_cast<std::uint32_t>(m)};
  out.colour_start = {0, 1};
  return out;
}

// The strips schedule (SweepOrder::strips): a contact belongs to the lower strip of its
// moving bodies; a strip's contacts then touch that strip and the next only, so two strips
// of one parity share no moving body: colour 0 is the even strips, colour 1 the odd ones,
// and a strip is one block, swept in the base order by one thread. A contact whose bodies
// lie more than one strip apart (a candidate across a strip, in a fast flow) breaks
// that: the step is then swept as one group, in the base order.
Schedule strip_schedule(const ContactSystem& s, std::span<const std::uint32_t> base) {
  const std::size_t m = s.rows.size();
  auto row_at = [&](std::size_t q) { return base.empty() ? static_cast<std::uint32_t>(q) : base[q]; };
  if (s.strip.size() != s.bodies.size()) return one_group(base, m);
  std::int32_t strips = 0;
  for (const std::int32_t k : s.strip) strips = std::max(strips, k + 1);
  if (strips < 2) return one_group(base, m);
  std::vector<std::int32_t> strip_of(m);
  for (std::size_t q = 0; q < m; ++q) {
    const ContactRow& r = s.rows[row_at(q)];
    const std::int32_t a = s.strip[static_cast<std::size_t>(r.bi)];
    const std::int32_t b = s.strip[static_cast<std::size_t>(r.bj)];
    if (a >= 0 && b >= 0 && std::abs(a - b) > 1) return one_group(base, m);
    strip_of[q] = a < 0 ? std::max(b, 0) : b < 0 ? a : std::min(a, b);
  }
  // Stable counting sort by (parity, strip): even strips first.
  auto slot = [&](std::int32_t k) { return static_cast<std::size_t>(k % 2 == 0 ? k / 2 : (strips + 1) / 2 + k / 2); };
  std::vector<std::uint32_t> first(static_cast<std::size_t>(strips) + 1, 0);
  for (std::size_t q = 0; q < m; ++q) ++first[slot(strip_of[q]) + 1];
  for (std::size_t k = 0; k < static_cast<std::size_t>(strips); ++k) first[k + 1] += first[k];
  std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
  Schedule out;
  out.positions.resize(m);
  for (std::size_t q = 0; q < m; ++q) out.positions[next[slot(strip_of[q])]++] = row_at(q);
  out.coloured = true;
  out.block_start.assign(first.begin(), first.end());
  out.colour_start = {0, static_cast<std::uint32_t>((strips + 1) / 2), static_cast<std::uint32_t>(strips)};
  return out;
}

}  // namespace

Schedule row_schedule(const ContactSystem& s, SweepOrder order,
                      std::span<const std::uint32_t> base) {
  CDPILE_DEBUG_CHECK(base.empty() || base.size() == s.rows.size(),
                     "a sweep order is a permutation of the rows");
  if (order == SweepOrder::pair || s.rows.empty()) return one_group(base, s.rows.size());
  return strip_schedule(s, base);
}

RowsInScheduleOrder::RowsInScheduleOrder(ContactSystem& s, Schedule& plan, bool bodies_too)
    : s_(s) {
  if (!plan.coloured) return;
  row_of_ = plan.positions;
  const std::size_t m = s.rows.size(), n = s.bodies.size();
  std::vector<std::int32_t> new_body;
  if (bodies_too && s.strip.size() == n) {
    // A stable counting sort of the bodies by strip, the static ones (strip -1) last.
    std::int32_t strips = 0;
    for (const std::int32_t k : s.strip) strips = std::max(strips, k + 1);
    auto slot = [&](std::size_t b) {
      return static_cast<std::size_t>(s.strip[b] < 0 ? strips : s.strip[b]);
    };
    std::vector<std::size_t> next(static_cast<std::size_t>(strips) + 2, 0);
    for (std::size_t b = 0; b < n; ++b) ++next[slot(b) + 1];
    for (std::size_t k = 1; k < next.size(); ++k) next[k] += next[k - 1];
    body_of_.resize(n);
    new_body.resize(n);
    for (std::size_t b = 0; b < n; ++b) {
      const std::size_t at = next[slot(b)]++;
      body_of_[at] = static_cast<std::int32_t>(b);
      new_body[b] = static_cast<std::int32_t>(at);
    }
    s.spare_bodies.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      s.spare_bodies[k] = s.bodies[static_cast<std::size_t>(body_of_[k])];
    s.bodies.swap(s.spare_bodies);
  }
  s.spare_rows.resize(m);
  for_each_range(m, s.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t q = first; q < last; ++q) {
      ContactRow& r = s.spare_rows[q];
      r = s.rows[row_of_[q]];
      if (!new_body.empty()) {
        r.bi = new_body[static_cast<std::size_t>(r.bi)];
        r.bj = new_body[static_cast<std::size_t>(r.bj)];
      }
      plan.positions[q] = static_cast<std::uint32_t>(q);
    }
  });
  s.rows.swap(s.spare_rows);
}

RowsInScheduleOrder::~RowsInScheduleOrder() {
  if (row_of_.empty()) return;
  // row_of_ is a permutation: every thread writes rows of its own
  for_each_range(row_of_.size(), s_.team, [&](std::size_t first, std::size_t last) {
    for (std::size_t q = first; q < last; ++q) {
      ContactRow& r = s_.spare_rows[row_of_[q]];
      r = s_.rows[q];
      if (!body_of_.empty()) {
        r.bi = body_of_[static_cast<std::size_t>(r.bi)];
        r.bj = body_of_[static_cast<std::size_t>(r.bj)];
      }
    }
  });
  s_.rows.swap(s_.spare_rows);
  if (body_of_.empty()) return;
  for (std::size_t k = 0; k < body_of_.size(); ++k)
    s_.spare_bodies[static_cast<std::size_t>(body_of_[k])] = s_.bodies[k];
  s_.bodies.swap(s_.spare_bodies);
}

namespace {

bool on_one_thread(const Schedule& s, const Team* team) {
  return !team || team->size() == 1 || !s.coloured || s.size() < team->smallest_shared();
}

/// The first block of thread u of `threads` over blocks [b0, b1): the ranges hold about
/// equal numbers of positions (a strip's contacts, or its active ones in a face, vary
/// with the pile's height and its rearrangements), each block whole. The ranges are
/// fixed, not handed out block by block: a thread keeps its part of the pile in its
/// core's caches from pass to pass (handing blocks out as threads came free made a
/// 16 000-grain window 35 to 45 % slower on 2 threads; docs/performance.md, "Threads").
std::size_t split(const Schedule& s, std::size_t b0, std::size_t b1, std::size_t threads,
                  std::size_t u) {
  if (u == 0) return b0;
  if (u >= threads) return b1;
  const std::size_t p0 = s.block_start[b0], n = s.block_start[b1] - p0;
  const auto at = std::lower_bound(s.block_start.begin() + static_cast<std::ptrdiff_t>(b0),
                                   s.block_start.begin() + static_cast<std::ptrdiff_t>(b1),
                                   p0 + n * u / threads);
  return static_cast<std::size_t>(at - s.block_start.begin());
}

}  // namespace

void for_each_block(const Schedule& s, Team* team, bool backward,
                    const std::function<void(std::size_t, std::size_t, std::size_t)>& work) {
  const std::size_t colours = s.colours();
  auto colour_blocks = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k) {
      const std::size_t b = backward ? to - 1 - (k - from) : k;
      work(s.block_start[b], s.block_start[b + 1], b);
    }
  };
  // A small schedule runs on one thread: its colours take less time than the team takes
  // to meet at a barrier. The blocks are the same, so the numbers are too.
  if (on_one_thread(s, team)) {
    for (std::size_t k = 0; k < colours; ++k) {
      const std::size_t c = backward ? colours - 1 - k : k;
      colour_blocks(s.colour_start[c], s.colour_start[c + 1]);
    }
    return;
  }
  const auto threads = static_cast<std::size_t>(team->size());
  team->run([&](int t) {
    const auto u = static_cast<std::size_t>(t);
    for (std::size_t k = 0; k < colours; ++k) {
      const std::size_t c = backward ? colours - 1 - k : k;
      const std::size_t b0 = s.colour_start[c], b1 = s.colour_start[c + 1];
      colour_blocks(split(s, b0, b1, threads, u), split(s, b0, b1, threads, u + 1));
      if (k + 1 < colours) team->barrier();
    }
  });
}

void for_all_blocks(const Schedule& s, Team* team,
                    const std::function<void(std::size_t, std::size_t, std::size_t)>& work) {
  auto blocks = [&](std::size_t from, std::size_t to) {
    for (std::size_t b = from; b < to; ++b) work(s.block_start[b], s.block_start[b + 1], b);
  };
  if (on_one_thread(s, team)) {
    blocks(0, s.blocks());
    return;
  }
  const auto threads = static_cast<std::size_t>(team->size());
  team->run([&](int t) {
    const auto u = static_cast<std::size_t>(t);
    blocks(split(s, 0, s.blocks(), threads, u), split(s, 0, s.blocks(), threads, u + 1));
  });
}

void for_each_range(std::size_t n, Team* team,
                    const std::function<void(std::size_t, std::size_t)>& work) {
  if (!team || team->size() == 1 || n < team->smallest_shared()) {
    work(0, n);
    return;
  }
  const auto threads = static_cast<std::size_t>(team->size());
  team->run([&](int t) {
    const auto u = static_cast<std::size_t>(t);
    work(n * u / threads, n * (u + 1) / threads);
  });
}

}  // namespace cdpile::cd
