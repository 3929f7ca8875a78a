// ADMM (cd::solve_admm, admm.hpp) on steps that export_steps wrote, from each step's warm
// start (step-K.r0), to the engine's tolerance in the engine's maxm scale: iterations,
// factorisations, CPU [ms] split into the setup (the power iteration, the ordering and
// the first factorisation) and the iterations, and the natural-map residual reached
// beside the engine's own impulses' (step-K.r). docs/performance.md, "A factorised solver".
//
// Usage: admm_on_steps [--compliance C] [--rho R] [--tolerance T] [--max N] [--trace K]
//                      [--relaxation A] STEP.dat...
//   C: the compliance 1/(k h^2) of the step (the smallest on W's diagonal; 0: rigid);
//   R: the first rho relative to D (default: sqrt(lambda_min lambda_max));
//   --trace K: a line every K iterations.
#include "cdpile/cd/admm.hpp"
#include "cdpile/cd/delassus.hpp"
#include "cdpile/io/siconos.hpp"

#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace cd = cdpile::cd;

namespace {

Eigen::VectorXd read_row(const std::string& path, Eigen::Index n) {
  std::ifstream in(path);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  if (static_cast<Eigen::Index>(v.size()) != n) return Eigen::VectorXd::Zero(n);
  return Eigen::Map<Eigen::VectorXd>(v.data(), n);
}

}  // namespace

int main(int argc, char** argv) {
  cd::AdmmOptions o;
  o.tolerance = 1e-6;
  o.velocity_floor = 9.81 * 1e-4;  // g h of the paper's runs
  o.max_iterations = 5000;
  int trace = 0;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has = a + 1 < argc;
    if (arg == "--compliance" && has)
      o.compliance = std::stod(argv[++a]);
    else if (arg == "--rho" && has)
      o.rho = std::stod(argv[++a]);
    else if (arg == "--tolerance" && has)
      o.tolerance = std::stod(argv[++a]);
    else if (arg == "--max" && has)
      o.max_iterations = std::stoi(argv[++a]);
    else if (arg == "--trace" && has)
      trace = std::stoi(argv[++a]);
    else if (arg == "--relaxation" && has)
      o.relaxation = std::stod(argv[++a]);
    else
      files.push_back(arg);
  }
  if (files.empty()) {
    std::cerr << "usage: admm_on_steps [--compliance C] [--rho R] [--tolerance T] [--max N] "
                 "[--trace K] STEP.dat...\n";
    return 2;
  }
  if (trace > 0)
    o.on_iteration = [&](int k, double law, double primal, double dual, double rho) {
      if (k % trace == 0)
        std::printf("  %5d law %.3e primal %.3e dual %.3e rho %.3e\n", k, law, primal, dual, rho);
    };
  std::printf(
      "file\tcontacts\titerations\tfactorisations\tlaw\tconverged\tcpu_ms\tnatural_map\t"
      "engine_natural_map\tengine_law\n");
  try {
    for (const std::string& file : files) {
      const cd::DelassusProblem p = cdpile::io::read_siconos_fc2d(file);
      const std::string stem = file.substr(0, file.size() - 4);
      Eigen::VectorXd r = read_row(stem + ".r0", 2 * p.contacts());
      const Eigen::VectorXd engine = read_row(stem + ".r", 2 * p.contacts());
      const std::clock_t cpu = std::clock();
      const cd::AdmmReport rep = cd::solve_admm(p, r, o);
      const double ms = 1e3 * static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC;
      std::printf("%s\t%ld\t%d\t%d\t%.3e\t%d\t%.1f\t%.3e\t%.3e\t%.3e\n", file.c_str(),
                  static_cast<long>(p.contacts()), rep.iterations, rep.factorisations, rep.residual,
                  rep.converged ? 1 : 0, ms, cd::natural_map_residual(p, r),
                  cd::natural_map_residual(p, engine),
                  cd::admm_law_residual(p, engine, o.velocity_floor));
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::cerr << "admm_on_steps: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
