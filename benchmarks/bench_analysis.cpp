// Time per frame of the analyses against the number of contacts, on a synthetic dense
// pile: disks of diameter D = 1 on a triangular lattice (each grain touching its six
// neighbours, about 3 contacts per grain), a pile 4 times wider than high, 8 % of the
// contacts critical at random (the paper's nu_c; the cost does not depend on it much).
//   localnu:   one CGAL Kd_tree per frame, one query of the largest radius per contact for
//              all radii 1..20 D plus the pdf radius (LocalNuStudy::add_frame, no map);
//   critical:  select_contacts + pile_state of one frame (eqs 1-2);
//   correlate: pooling the per-frame sums of a 20-frame localnu product, per frame.
// Counters: contacts, and the time per contact. Run: bench_analysis [--benchmark_filter=...].
#include "cdpile/analysis/studies.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

using namespace cdpile;
using namespace cdpile::analysis;

namespace {

struct Pile {
  Grains grains;
  Contacts contacts;
};

// A triangular packing with about `target` grain-grain contacts.
Pile dense_pile(std::size_t target, std::uint64_t seed) {
  const double d = 1.0;
  // grains ~ target / 3; width = 4 x height (in rows of sqrt(3)/2 D)
  const double grains = static_cast<double>(target) / 3.0;
  const auto rows =
      static_cast<std::size_t>(std::ceil(std::sqrt(grains / 4.0 * std::sqrt(3.0) / 2.0)));
  const auto cols = static_cast<std::size_t>(std::ceil(grains / static_cast<double>(rows)));
  Pile p;
  std::vector<std::vector<std::int32_t>> id(rows, std::vector<std::int32_t>(cols));
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      id[r][c] = static_cast<std::int32_t>(p.grains.size());
      p.grains.add_disk(0.5 * d, 2500.0,
                        Vec2((static_cast<double>(c) + 0.5 * static_cast<double>(r % 2) + 0.5) * d,
                             (0.5 + static_cast<double>(r) * std::sqrt(3.0) / 2.0) * d));
    }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double mu = 0.5;
  auto touch = [&](std::int32_t a, std::int32_t b) {
    if (p.contacts.size() >= target) return;
    const Vec2 xa = p.grains.position[static_cast<std::size_t>(a)],
               xb = p.grains.position[static_cast<std::size_t>(b)];
    const Vec2 n = (xa - xb).normalized();
    const double fn = 1.0 + u(rng);
    const double ft = (u(rng) < 0.08 ? 1.0 : 0.9 * u(rng)) * mu * fn;
    p.contacts.push_back(a, b, 0.5 * (xa + xb), n, fn, ft, 0.0, ContactStatus::stick);
  };
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      if (c + 1 < cols) touch(id[r][c], id[r][c + 1]);
      if (r + 1 < rows) {
        // the two neighbours above (odd rows are shifted right by D/2)
        const std::size_t left = r % 2 ? c : (c > 0 ? c - 1 : cols);
        const std::size_t right = r % 2 ? c + 1 : c;
        if (left < cols) touch(id[r][c], id[r + 1][left]);
        if (right < cols) touch(id[r][c], id[r + 1][right]);
      }
    }
  return p;
}

void set_counters(benchmark::State& state, std::size_t contacts) {
  state.counters["contacts"] = static_cast<double>(contacts);
  // the time per contact (benchmark prints it with its unit)
  state.counters["per_contact"] =
      benchmark::Counter(static_cast<double>(contacts) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_LocalNuFrame(benchmark::State& state) {
  const Pile p = dense_pile(static_cast<std::size_t>(state.range(0)), 1);
  const ContactSet set = select_contacts(p.contacts, p.grains.species, Friction{}, CriticalRule{});
  LocalNuStudy study(default_localnu_options());
  std::int64_t frame = 0;
  for (auto _ : state) {
    study.add_frame(0, "bench", frame, frame, 1.0, 1.0, set, true, false);
    ++frame;
  }
  set_counters(state, set.size());
}

void BM_CriticalFrame(benchmark::State& state) {
  const Pile p = dense_pile(static_cast<std::size_t>(state.range(0)), 2);
  const std::int64_t free = free_grain_count(p.grains);
  std::size_t n = 0;
  for (auto _ : state) {
    const ContactSet set =
        select_contacts(p.contacts, p.grains.species, Friction{}, CriticalRule{});
    const PileState s = pile_state(set, p.grains.species, free, 1.0, RattlerRule::exclude);
    benchmark::DoNotOptimize(s.nu);
    n = set.size();
  }
  set_counters(state, n);
}

void BM_CorrelateFrame(benchmark::State& state) {
  const Pile p = dense_pile(static_cast<std::size_t>(state.range(0)), 3);
  const ContactSet set = select_contacts(p.contacts, p.grains.species, Friction{}, CriticalRule{});
  LocalNuStudy study(default_localnu_options());
  const int frames = 20;
  for (int f = 0; f < frames; ++f)
    study.add_frame(0, "bench", f, f, 0.1 * f, 1.0, set, true, false);
  const Product lp = study.product();
  for (auto _ : state) {
    Product c = correlate(lp, CorrelateOptions{});
    benchmark::DoNotOptimize(c.tables.size());
  }
  state.SetItemsProcessed(state.iterations() * frames);  // items = frames
  state.counters["contacts"] = static_cast<double>(set.size());
}

}  // namespace

BENCHMARK(BM_LocalNuFrame)->Arg(2000)->Arg(8000)->Arg(32000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CriticalFrame)->Arg(2000)->Arg(8000)->Arg(32000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CorrelateFrame)->Arg(2000)->Arg(32000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
