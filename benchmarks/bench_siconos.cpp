// Our NSGS (cd::solve_nsgs, the engine's exact 2D local solver) on Siconos' three 2D
// frictional contact problems (667, 2020 and 7002 contacts), from r = 0 to the
// natural-map residual 1e-5 within 10 000 sweeps, as Siconos' own tests ask. Each
// iteration is one full solve (reading the file is not timed). Counters: contacts,
// sweeps, final residual, converged. benchmarks/siconos_reference.py times Siconos' own
// fc2d NSGS on the same files; docs/performance.md compares the two.
//
// Run: bench_siconos [--data DIR] [--benchmark_filter=...]
// (DIR defaults to tests/data/siconos-fc2d of the source tree, which holds the 667- and
// 2020-contact problems; the 7002-contact one is reported absent unless DIR holds it:
// tests/data/siconos-fc2d/README.md).
#include "cdpile/cd/delassus.hpp"
#include "cdpile/io/siconos.hpp"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace cd = cdpile::cd;
namespace io = cdpile::io;

std::string g_data = CDPILE_SICONOS_DATA;

const char* const kFiles[] = {
    "fc2d_granularflowonwall_00667_00000.dat",
    "fc2d_granularflowonwall_02020_00213.dat",
    "fc2d_granularflowonwall_07002_00801.dat",
};

void BM_SiconosNsgs(benchmark::State& state, const std::string& file) {
  const std::string path = g_data + "/" + file;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("absent: " + path).c_str());
    return;
  }
  const cd::DelassusProblem p = io::read_siconos_fc2d(path);
  const cd::NsgsOptions options{.tolerance = 1e-5, .max_sweeps = 10000};
  cd::NsgsReport report;
  for (auto _ : state) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(2 * p.contacts());  // cold start, as Siconos
    report = cd::solve_nsgs(p, r, options);
    benchmark::DoNotOptimize(r.data());
  }
  state.counters["contacts"] = static_cast<double>(p.contacts());
  state.counters["sweeps"] = report.sweeps;
  state.counters["residual"] = report.residual;
  state.counters["converged"] = report.converged ? 1 : 0;
  // Sweeps per CPU second (Google Benchmark divides by the CPU time of all iterations).
  state.counters["sweeps/s"] =
      benchmark::Counter(report.sweeps, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> rest{argv[0]};
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--data") == 0 && k + 1 < argc)
      g_data = argv[++k];
    else
      rest.push_back(argv[k]);
  }
  for (const char* file : kFiles)
    benchmark::RegisterBenchmark(("BM_SiconosNsgs/" + std::string(file).substr(24, 5)).c_str(),
                                 BM_SiconosNsgs, std::string(file))
        ->Unit(benchmark::kMillisecond)
        ->MinTime(1.0);
  int rest_argc = static_cast<int>(rest.size());
  benchmark::Initialize(&rest_argc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(rest_argc, rest.data())) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
