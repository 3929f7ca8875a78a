// Cost of a tilt step of the Contact Dynamics engine against the number of grains N, on
// settled piles made by the `deposit` tool (benchmarks/make_piles.sh writes them):
// N = 500, 1000, 4000, 16000 free grains in boxes 15, 30, 120 and 480 mean diameters
// wide, and 64000 in 1920 D (16 copies of the 4000-grain pile side by side, made by
// benchmarks/tile_pile.cpp: a deposit of that size costs hours), so every pile has the
// depth of the paper's (4000 grains, 120 D) and only the width grows: the sweeps NSGS
// needs depend on the depth, and the cost per contact update is what is compared across N.
//
// Each benchmark rebuilds the engine from the pile as tilt-cd does (impulses warm-started
// from the pile's forces) and times `steps` steps with gravity turning at the default
// 0.001 degree per step from 0 (the start of a paper run), default solver settings.
// Counters: grains, contacts (active, mean per step), sweeps per step, contact updates
// per second (local solves / wall time), unconverged steps, heap bytes held by the engine
// per grain, and the process's peak resident set. After the runs: the per-stage profile
// of a step (StepProfile) and a check that the engine's memory is linear in N.
//
// Run: bench_engine [--piles DIR] [--steps K] [--benchmark_repetitions=R] [--benchmark_filter=...]
// (DIR defaults to ./bench-piles, or $CDPILE_BENCH_PILES; K to 200 steps).
#include "cdpile/cd/engine.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/sim/tilt.hpp"

#include <benchmark/benchmark.h>

#include <malloc.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <new>
#include <numbers>
#include <string>
#include <vector>

// --- heap accounting: live bytes through the global operator new -------------------
// The engine's memory is its vectors; counting the bytes live on the heap before it is
// built and after it has stepped gives what it holds, exactly, without reading private
// members. malloc_usable_size is used on both sides so the books balance.
namespace {
std::atomic<std::int64_t> g_live{0};
}  // namespace

void* operator new(std::size_t n) {
  void* p = std::malloc(n == 0 ? 1 : n);
  if (!p) throw std::bad_alloc();
  g_live.fetch_add(static_cast<std::int64_t>(malloc_usable_size(p)), std::memory_order_relaxed);
  return p;
}
void operator delete(void* p) noexcept {
  if (!p) return;
  g_live.fetch_sub(static_cast<std::int64_t>(malloc_usable_size(p)), std::memory_order_relaxed);
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }

namespace {

using namespace cdpile;

std::string g_piles = [] {
  const char* env = std::getenv("CDPILE_BENCH_PILES");
  return std::string(env ? env : "bench-piles");
}();
std::int64_t g_steps = 200;

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in kB on Linux
}

/// CPU time of this thread [s]: the machine is shared, so wall time includes the time
/// other processes held the core; CPU time does not.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Result {
  std::int64_t grains = 0;
  double contacts = 0, engine_bytes = 0, ms_per_step = 0, cpu_ms_per_step = 0, sweeps = 0;
  cd::StepProfile profile;
};
std::map<std::int64_t, Result> g_results;

void BM_TiltStep(benchmark::State& state) {
  const std::int64_t n = state.range(0);
  const std::string path = g_piles + "/pile_" + std::to_string(n) + ".h5";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("no pile " + path + ": run benchmarks/make_piles.sh first").c_str());
    return;
  }
  sim::PileInput pile;
  {
    io::Input in(path);
    pile = sim::read_pile(in.hdf5());
  }
  // The settings tilt-cd would use for this pile: defaults, alert distance 0.1 D.
  cd::Settings settings;
  const auto d = pile.parameters.find("diameter_mean_m");
  const double diameter = d != pile.parameters.end() ? std::get<double>(d->second) : 1e-3;
  settings.alert_distance = 0.1 * diameter;

  const std::int64_t heap_before = g_live.load();
  Result res;
  {
    cd::Engine engine(pile.box, pile.grains, settings);
    engine.set_state(sim::warm_start_state(pile.contacts, settings.time_step));
    engine.reset_profile();

    const double rate = 0.001 * std::numbers::pi / 180.0;  // tilt-cd's default, per step
    std::int64_t step = 0, contacts = 0, unconverged = 0;
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    for (auto _ : state) {
      ++step;
      const cd::StepReport r = engine.step(static_cast<double>(step) * rate);
      contacts += r.contacts;
      unconverged += r.converged ? 0 : 1;
    }
    const double cpu = cpu_seconds() - cpu_start;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const cd::StepProfile& p = engine.profile();
    // Live heap with the engine built and warm: what it holds (the pile copy outside).
    res.engine_bytes = static_cast<double>(g_live.load() - heap_before);
    res.grains = static_cast<std::int64_t>(pile.grains.size());
    res.contacts = static_cast<double>(contacts) / static_cast<double>(step);
    res.ms_per_step = 1e3 * seconds / static_cast<double>(step);
    res.cpu_ms_per_step = 1e3 * cpu / static_cast<double>(step);
    res.sweeps = static_cast<double>(p.sweeps) / static_cast<double>(p.steps);
    res.profile = p;

    state.counters["grains"] = static_cast<double>(res.grains);
    state.counters["contacts"] = res.contacts;
    state.counters["sweeps/step"] = res.sweeps;
    // Local solves (sweeps x contact candidates) per CPU second.
    state.counters["updates/s"] = static_cast<double>(p.contact_updates) / cpu;
    state.counters["unconverged"] = static_cast<double>(unconverged);
    state.counters["B/grain"] = res.engine_bytes / static_cast<double>(res.grains);
    state.counters["peakRSS_MB"] = peak_rss_mb();
  }
  // With --benchmark_repetitions, the summary keeps the least disturbed run.
  auto old = g_results.find(n);
  if (old == g_results.end() || res.cpu_ms_per_step < old->second.cpu_ms_per_step)
    g_results[n] = res;
}

void print_summary() {
  if (g_results.empty()) return;
  std::printf(
      "\nPer-stage wall time of a step (StepProfile), %% of the staged time; ms/step\n"
      "wall and CPU; ns per local solve (solve stage / (sweeps x candidates)):\n");
  std::printf("%7s %8s %8s %7s %7s %7s %9s %8s %7s %8s %8s %7s %9s\n", "N", "wall_ms", "cpu_ms",
              "sweeps", "detect", "frames", "delassus", "warm", "solve", "upd_vel", "upd_pos",
              "store", "ns/update");
  for (const auto& [n, r] : g_results) {
    const auto& p = r.profile;
    const double t = p.total();
    auto pc = [&](double x) { return 100.0 * x / t; };
    std::printf(
        "%7lld %8.3f %8.3f %7.1f %6.1f%% %6.1f%% %8.1f%% %7.1f%% %6.1f%% %7.1f%% %7.1f%% "
        "%6.1f%% %9.1f\n",
        static_cast<long long>(n), r.ms_per_step, r.cpu_ms_per_step, r.sweeps, pc(p.detect),
        pc(p.frames), pc(p.delassus), pc(p.warm_start), pc(p.solve), pc(p.update_velocities),
        pc(p.update_positions), pc(p.store),
        1e9 * p.solve / static_cast<double>(std::max<std::int64_t>(p.contact_updates, 1)));
  }
  std::printf("\nMemory held by the engine (heap bytes after the steps):\n");
  std::printf("%7s %9s %10s %11s %12s\n", "N", "grains", "contacts", "bytes", "bytes/grain");
  double lo = 1e300, hi = 0;
  for (const auto& [n, r] : g_results) {
    const double per = r.engine_bytes / static_cast<double>(r.grains);
    lo = std::min(lo, per);
    hi = std::max(hi, per);
    std::printf("%7lld %9lld %10.0f %11.0f %12.1f\n", static_cast<long long>(n),
                static_cast<long long>(r.grains), r.contacts, r.engine_bytes, per);
  }
  // Linear in N means a constant cost per grain; vectors grow by doubling, so up to a
  // factor 2 between sizes is capacity slack, not growth.
  std::printf("bytes/grain from %.1f to %.1f (ratio %.2f): %s\n", lo, hi, hi / lo,
              hi / lo < 2.0 ? "linear in N (within vector capacity slack)" : "NOT linear in N");
  std::printf("peak resident set of the process: %.1f MB\n", peak_rss_mb());
}

}  // namespace

int main(int argc, char** argv) {
  // Our own options first (Google Benchmark rejects unknown ones).
  std::vector<char*> rest{argv[0]};
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--piles") == 0 && k + 1 < argc)
      g_piles = argv[++k];
    else if (std::strcmp(argv[k], "--steps") == 0 && k + 1 < argc)
      g_steps = std::atoll(argv[++k]);
    else
      rest.push_back(argv[k]);
  }
  if (g_steps < 1) {
    std::fprintf(stderr, "bench_engine: --steps must be at least 1\n");
    return 2;
  }
  // Every size runs the same number of steps: the benchmark's iterations are fixed.
  benchmark::RegisterBenchmark("BM_TiltStep", BM_TiltStep)
      ->ArgName("N")
      ->Arg(500)
      ->Arg(1000)
      ->Arg(4000)
      ->Arg(16000)
      ->Arg(64000)
      ->Iterations(g_steps)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  int rest_argc = static_cast<int>(rest.size());
  benchmark::Initialize(&rest_argc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(rest_argc, rest.data())) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_summary();
  return 0;
}
