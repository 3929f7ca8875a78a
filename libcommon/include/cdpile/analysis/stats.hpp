/// Means and standard errors, the way every analysis tool reports them.
///
/// A standard error needs at least two independent samples; with fewer it is absent
/// (an empty optional, printed as the missing-value marker), never NaN.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cdpile::analysis {

/// Mean, sample standard deviation and standard error of the mean of n samples.
struct Summary {
  std::int64_t n = 0;
  std::optional<double> mean;  ///< absent when n = 0
  std::optional<double> sd;    ///< sample sd (n - 1), absent when n < 2
  std::optional<double> se;    ///< sd / sqrt(n), absent when n < 2
};

/// Summary of a list of samples (the independent units: runs, frames or contacts).
Summary summarize(std::span<const double> samples);

/// Running sums of a quantity over a group: count, sum and sum of squares.
struct Sums {
  std::int64_t n = 0;
  double sum = 0.0, sum2 = 0.0;
  void add(double x) {
    ++n;
    sum += x;
    sum2 += x * x;
  }
  void add(const Sums& o) {
    n += o.n;
    sum += o.sum;
    sum2 += o.sum2;
  }
  /// Mean and the naive standard error sd/sqrt(n), treating the samples as independent.
  Summary summary() const;
};

/// Which independent units a pooled standard error was computed over.
enum class SeOver : std::uint8_t { none = 0, contacts = 1, frames = 2, runs = 3 };
const char* se_over_name(SeOver s);

/// A pooled mean over clusters of samples (e.g. all critical contacts of the frames of a
/// theta window, clustered by run): mean = sum S_c / sum N_c, and the cluster-robust
/// standard error of that ratio,
///     se^2 = C/(C-1) sum_c (S_c - mean N_c)^2 / (sum_c N_c)^2,
/// over the C clusters with N_c > 0. With one cluster the naive per-sample error of the
/// pooled sums is used instead and `over` says so.
struct Pooled {
  std::int64_t n = 0;         ///< samples
  std::int64_t clusters = 0;  ///< clusters with samples
  std::optional<double> mean, se;
  SeOver over = SeOver::none;
};
Pooled pooled_mean(std::span<const Sums> clusters, SeOver cluster_kind);

}  // namespace cdpile::analysis
