/// localnu: nu_i(r) around every contact, its sums over critical contacts per frame (eq
/// 3), the pdfs P_c and P_nc and the nu field (Figs 3, 5). Definitions: docs/analysis.md.
#pragma once

#include "cdpile/analysis/local_state.hpp"
#include "cdpile/analysis/run_record.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cdpile::analysis {

struct LocalNuOptions {
  std::vector<double> radii;  ///< [D], ascending; default 1..20
  bool exclude_self = false;
  EdgeRule edge = EdgeRule::keep;
  double pdf_radius = 6.0;  ///< [D]
  std::size_t pdf_bins = 50;
  std::optional<ThetaRange> pdf_theta;  ///< default: the loading phase of each run
  double map_radius = 6.0;              ///< [D]
  double map_spacing = 1.0;             ///< [D]
  double nu_c = 0.08;                   ///< threshold of the map (Fig 5)
  bool per_contact = false;             ///< table of nu_i(r) of every contact of the map frame
};

LocalNuOptions default_localnu_options();

class LocalNuStudy {
 public:
  explicit LocalNuStudy(LocalNuOptions opt);
  /// Adds one frame: its contacts that count (from select_contacts), the run's mean
  /// diameter D [m], whether it is in the loading phase (pdf pooling by default) and
  /// whether it is the frame to map. Returns the frame's local states (for callers that
  /// want more).
  void add_frame(std::int64_t run, const std::string& run_name, std::int64_t frame,
                 std::int64_t step, std::optional<double> theta, double diameter,
                 const ContactSet& set, bool loading, bool map_this);
  /// The length unit of the inputs' coordinates and diameters ("m" for runs; a contact
  /// table's declared unit; "" when unknown or when the inputs differ): columns get it as
  /// their unit ("?" when unknown), and the map's results are named with the `_m` suffix
  /// only in metres (else without a suffix, beside the parameter `length_unit`).
  void set_length_unit(const std::string& unit) { length_unit_ = unit; }
  /// A note added to the product (e.g. duplicate rows merged in an input).
  void add_note(const std::string& note) { extra_notes_.push_back(note); }
  /// Adds run number `run` from its summary (analysis/run_summary.hpp): its frames' rows,
  /// its sums and its pdf counts, as add_frame added them when the summary was made with
  /// these options (the caller checks that: require_reading).
  void add_summary(std::int64_t run, const Product& summary);
  /// The map (table `map` and its map_* values, from a summary) of input `run`, thresholded
  /// at the options' nu_c: what add_frame makes of the frame to map.
  void set_map(std::int64_t run, Table map, Values info);
  const LocalNuOptions& options() const { return opt_; }
  Product product() const;
  std::size_t frames() const { return frames_; }

 private:
  LocalNuOptions opt_;
  std::string length_unit_ = "m";
  std::vector<std::string> extra_notes_;
  std::vector<double> query_;       // radii of the query [D]: radii + pdf radius, sorted
  std::vector<std::size_t> out_k_;  // index in query_ of each output radius
  std::size_t pdf_k_ = 0;
  std::size_t frames_ = 0;
  Table frames_t_, states_t_, contacts_t_, map_t_;
  Histogram pc_, pnc_;
  std::int64_t pdf_frames_ = 0;
  bool mapped_ = false;
  Values map_info_;
};

}  // namespace cdpile::analysis
