// localnu: the local state nu_i(r) of every contact (eq 1 on a disk of radius r), its
// sums over critical contacts per frame (for eq 3), the pdfs P_c and P_nc at one radius
// (Fig 3) and the nu field on a grid (Fig 5).
#include "cdpile/analysis/studies.hpp"

#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cdpile::analysis {

namespace {

std::string radius_name(double r) {
  // nu_r6 or nu_r2.5: shortest round-trip text, '.' kept (valid in TSV and HDF5 names)
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, r);
  return "nu_r" + (ec == std::errc() ? std::string(buf, p) : std::to_string(r));
}
}  // namespace

LocalNuOptions default_localnu_options() {
  LocalNuOptions o;
  for (int k = 1; k <= 20; ++k) o.radii.push_back(k);
  return o;
}

LocalNuStudy::LocalNuStudy(LocalNuOptions opt) : opt_(std::move(opt)) {
  validate_radii(opt_.radii);
  if (!(opt_.pdf_radius > 0.0)) throw Error("pdf radius must be > 0");
  if (opt_.pdf_bins < 1) throw Error("pdf needs at least one bin");
  if (!(opt_.map_radius > 0.0) || !(opt_.map_spacing > 0.0))
    throw Error("map radius and spacing must be > 0");
  query_ = opt_.radii;
  if (std::find(query_.begin(), query_.end(), opt_.pdf_radius) == query_.end()) {
    query_.push_back(opt_.pdf_radius);
    std::sort(query_.begin(), query_.end());
  }
  for (double r : opt_.radii)
    out_k_.push_back(
        static_cast<std::size_t>(std::find(query_.begin(), query_.end(), r) - query_.begin()));
  pdf_k_ = static_cast<std::size_t>(std::find(query_.begin(), query_.end(), opt_.pdf_radius) -
                                    query_.begin());
  pc_ = Histogram(0.0, 1.0, opt_.pdf_bins);
  pnc_ = Histogram(0.0, 1.0, opt_.pdf_bins);

  frames_t_.name = "frames";
  frames_t_.title = "one row per frame: the state of the pile";
  for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"run", "", ColumnKind::integer},
           {"frame", "", ColumnKind::integer},
           {"step", "", ColumnKind::integer},
           {"theta", "deg", ColumnKind::real},
           {"diameter", "m", ColumnKind::real},
           {"N", "", ColumnKind::integer},
           {"Nc", "", ColumnKind::integer},
           {"nu", "", ColumnKind::real},
           {"loading", "", ColumnKind::integer}})
    frames_t_.add_column(n, u, k);
  states_t_.name = "states";
  states_t_.title =
      "one row per frame and radius: sums of nu_i(r) over the frame's critical contacts";
  for (auto [n, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"run", "", ColumnKind::integer},
           {"frame", "", ColumnKind::integer},
           {"theta", "deg", ColumnKind::real},
           {"r", "D", ColumnKind::real},
           {"n", "", ColumnKind::integer},
           {"sum", "", ColumnKind::real},
           {"sum2", "", ColumnKind::real},
           {"nu_bar", "", ColumnKind::real},
           {"se", "", ColumnKind::real}})
    states_t_.add_column(n, u, k);
}

void LocalNuStudy::add_frame(std::int64_t run, const std::string& run_name, std::int64_t frame,
                             std::int64_t step, std::optional<double> theta, double diameter,
                             const ContactSet& set, bool loading, bool map_this) {
  if (!(diameter > 0.0) || !std::isfinite(diameter))
    throw Error(run_name, "", "mean diameter must be > 0");
  ++frames_;
  std::vector<double> radii(query_.size());
  for (std::size_t k = 0; k < query_.size(); ++k) radii[k] = query_[k] * diameter;
  LocalStateOptions lo;
  lo.exclude_self = opt_.exclude_self;
  lo.edge = opt_.edge;
  lo.outline_bin = diameter;
  const NeighbourIndex index(set.point);
  std::vector<std::uint32_t> all(set.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<std::uint32_t>(k);
  const LocalStates s = local_states(index, set.point, set.critical, radii, all, lo);

  const std::int64_t nc = static_cast<std::int64_t>(set.critical_count());
  const std::int64_t n = static_cast<std::int64_t>(set.size());
  frames_t_.column("run").add_int(run);
  frames_t_.column("frame").add_int(frame);
  frames_t_.column("step").add_int(step);
  frames_t_.column("theta").add(theta);
  frames_t_.column("diameter").add(diameter);
  frames_t_.column("N").add_int(n);
  frames_t_.column("Nc").add_int(nc);
  frames_t_.column("nu").add(
      n > 0 ? std::optional<double>(static_cast<double>(nc) / static_cast<double>(n))
            : std::nullopt);
  frames_t_.column("loading").add_int(loading);

  const std::vector<Sums> sums = state_sums(s, set.critical, 1);  // eq (3) numerators
  for (std::size_t q = 0; q < opt_.radii.size(); ++q) {
    const Sums& x = sums[out_k_[q]];
    const Summary sm = x.summary();
    states_t_.column("run").add_int(run);
    states_t_.column("frame").add_int(frame);
    states_t_.column("theta").add(theta);
    states_t_.column("r").add(opt_.radii[q]);
    states_t_.column("n").add_int(x.n);
    states_t_.column("sum").add(x.sum);
    states_t_.column("sum2").add(x.sum2);
    states_t_.column("nu_bar").add(sm.mean);
    states_t_.column("se").add(sm.se);
  }

  const bool in_pdf = opt_.pdf_theta ? (theta && opt_.pdf_theta->contains(*theta)) : loading;
  if (in_pdf) {
    add_to_pdfs(s, set.critical, pdf_k_, pc_, pnc_);
    ++pdf_frames_;
  }

  if (map_this && !mapped_) {
    mapped_ = true;
    map_info_ = {{"map_run", run},
                 {"map_frame", frame},
                 {"map_step", step},
                 {"map_radius_D", opt_.map_radius},
                 {"map_spacing_D", opt_.map_spacing},
                 {"map_nu_c", opt_.nu_c},
                 {"map_diameter_m", diameter}};
    if (theta) map_info_["map_theta_deg"] = *theta;
    Field f;
    try {
      f = nu_field(set.point, set.critical, opt_.map_radius * diameter,
                   opt_.map_spacing * diameter);
    } catch (const FieldTooLarge& e) {
      char what[240];
      const std::string spacing = field("map_spacing");
      std::snprintf(
          what, sizeof what,
          "frame %lld: %s %g D gives a map of %.3g nodes over its contacts, more than %.0e; "
          "give a larger %s",
          static_cast<long long>(frame), spacing.c_str(), opt_.map_spacing, e.nodes,
          max_field_nodes, spacing.c_str());
      throw Error(run_name, "", what);
    }
    map_t_.name = "map";
    map_t_.title =
        "the nu field on a grid over the pile at one frame (Fig 5); row-major, x fastest";
    for (auto [nm, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
             {"ix", "", ColumnKind::integer},
             {"iy", "", ColumnKind::integer},
             {"x", "m", ColumnKind::real},
             {"y", "m", ColumnKind::real},
             {"x_D", "D", ColumnKind::real},
             {"y_D", "D", ColumnKind::real},
             {"contacts", "", ColumnKind::integer},
             {"critical", "", ColumnKind::integer},
             {"nu", "", ColumnKind::real},
             {"above", "", ColumnKind::integer}})
      map_t_.add_column(nm, u, k);
    for (std::size_t b = 0; b < f.ny; ++b)
      for (std::size_t a = 0; a < f.nx; ++a) {
        const double x = f.x0 + static_cast<double>(a) * f.dx,
                     y = f.y0 + static_cast<double>(b) * f.dx;
        const auto v = f.nu(a, b);
        map_t_.column("ix").add_int(static_cast<std::int64_t>(a));
        map_t_.column("iy").add_int(static_cast<std::int64_t>(b));
        map_t_.column("x").add(x);
        map_t_.column("y").add(y);
        map_t_.column("x_D").add(x / diameter);
        map_t_.column("y_D").add(y / diameter);
        map_t_.column("contacts").add_int(f.total[b * f.nx + a]);
        map_t_.column("critical").add_int(f.critical[b * f.nx + a]);
        map_t_.column("nu").add(v);
        map_t_.column("above").add(v ? std::optional<double>(*v >= opt_.nu_c ? 1.0 : 0.0)
                                     : std::nullopt);
      }
    map_info_["map_nx"] = static_cast<std::int64_t>(f.nx);
    map_info_["map_ny"] = static_cast<std::int64_t>(f.ny);
    map_info_["map_x0_m"] = f.x0;
    map_info_["map_y0_m"] = f.y0;
    map_info_["map_dx_m"] = f.dx;

    if (opt_.per_contact) {
      contacts_t_.name = "contacts";
      contacts_t_.title = "nu_i(r) of every contact of the mapped frame";
      for (auto [nm, u, k] :
           std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
               {"x", "m", ColumnKind::real},
               {"y", "m", ColumnKind::real},
               {"i", "", ColumnKind::integer},
               {"j", "", ColumnKind::integer},
               {"critical", "", ColumnKind::integer},
               {"sliding", "", ColumnKind::integer},
               {"mobilisation", "", ColumnKind::real}})
        contacts_t_.add_column(nm, u, k);
      for (double r : opt_.radii) contacts_t_.add_column(radius_name(r), "", ColumnKind::real);
      for (std::size_t c = 0; c < set.size(); ++c) {
        contacts_t_.column("x").add(set.point[c].x());
        contacts_t_.column("y").add(set.point[c].y());
        contacts_t_.column("i").add_int(set.i[c]);
        contacts_t_.column("j").add_int(set.j[c]);
        contacts_t_.column("critical").add_int(set.critical[c]);
        // NA, not 0, when the input says nothing about the solver's status
        contacts_t_.column("sliding").add(set.has_status ? std::optional<double>(set.sliding[c])
                                                         : std::nullopt);
        contacts_t_.column("mobilisation").add(set.mobilisation[c]);
        for (std::size_t q = 0; q < opt_.radii.size(); ++q)
          contacts_t_.columns[7 + q].add(s.nu(c, out_k_[q]));
      }
    }
  }
}

namespace {
// Appends the rows of `from` to `to` column by column (the same columns, by name, but
// those of `derived`, left to the caller), with column `run` set to `run`.
void append_rows(Table& to, const Table& from, std::int64_t run, const std::string& source,
                 const std::vector<std::string>& derived = {}) {
  const std::size_t n = from.rows();
  for (Column& c : to.columns) {
    if (std::find(derived.begin(), derived.end(), c.name) != derived.end()) continue;
    const Column* f = from.find(c.name);
    if (!f || f->kind != c.kind)
      throw Error(source, "/tables/" + from.name, "no " + std::string(c.name) + " column of its kind");
    if (c.name == "run")
      c.num.insert(c.num.end(), n, static_cast<double>(run));
    else if (c.kind == ColumnKind::text)
      c.text.insert(c.text.end(), f->text.begin(), f->text.end());
    else
      c.num.insert(c.num.end(), f->num.begin(), f->num.end());
  }
}
}  // namespace

void LocalNuStudy::add_summary(std::int64_t run, const Product& s) {
  const Table& frames = s.table("localnu_frames");
  append_rows(frames_t_, frames, run, s.source);
  // nu_bar and se from the sums, as add_frame computes them (a summary keeps the sums)
  const Table& states = s.table("localnu_states");
  append_rows(states_t_, states, run, s.source, {"nu_bar", "se"});
  const Column &n = states.column("n"), &sum = states.column("sum"), &sum2 = states.column("sum2");
  for (std::size_t k = 0; k < states.rows(); ++k) {
    const Summary sm = Sums{static_cast<std::int64_t>(n.num[k]), sum.num[k], sum2.num[k]}.summary();
    states_t_.column("nu_bar").add(sm.mean);
    states_t_.column("se").add(sm.se);
  }
  frames_ += frames.rows();
  const Table& pdf = s.table("localnu_pdf");
  if (pdf.rows() != pc_.count.size())
    throw Error(s.source, "/tables/localnu_pdf",
                std::to_string(pdf.rows()) + " bins, the pdfs have " +
                    std::to_string(pc_.count.size()));
  const Column &c = pdf.column("count_c"), &nc = pdf.column("count_nc");
  for (std::size_t b = 0; b < pc_.count.size(); ++b) {
    pc_.count[b] += static_cast<std::int64_t>(c.num[b]);
    pnc_.count[b] += static_cast<std::int64_t>(nc.num[b]);
  }
  const auto pdf_frames = s.result("localnu_pdf_frames");
  if (!pdf_frames) throw Error(s.source, "/results", "a summary without localnu_pdf_frames");
  pdf_frames_ += static_cast<std::int64_t>(*pdf_frames);
}

void LocalNuStudy::set_map(std::int64_t run, Table map, Values info) {
  // the threshold is the reader's: `above` again from nu
  Column& above = map.column("above");
  const Column& nu = map.column("nu");
  for (std::size_t k = 0; k < above.num.size(); ++k)
    above.num[k] = nu.defined(k) ? (nu.num[k] >= opt_.nu_c ? 1.0 : 0.0)
                                 : std::numeric_limits<double>::quiet_NaN();
  map_t_ = std::move(map);
  map_info_ = std::move(info);
  map_info_["map_run"] = run;
  map_info_["map_nu_c"] = opt_.nu_c;
  mapped_ = true;
}

Product LocalNuStudy::product() const {
  Product p;
  p.kind = "localnu";
  std::string radii;
  for (double r : opt_.radii) {
    char buf[64];
    auto [e, ec] = std::to_chars(buf, buf + sizeof buf, r);
    radii += (radii.empty() ? "" : ",") + std::string(buf, ec == std::errc() ? e : buf);
  }
  p.parameters = {{"radii_D", radii},
                  {"exclude_self", std::int64_t{opt_.exclude_self}},
                  {"edge", std::string(opt_.edge == EdgeRule::keep ? "keep" : "exclude")},
                  {"pdf_radius_D", opt_.pdf_radius},
                  {"pdf_bins", static_cast<std::int64_t>(opt_.pdf_bins)},
                  {"pdf_theta", std::string(opt_.pdf_theta ? "range" : "loading")}};
  if (opt_.pdf_theta) record_range(p.parameters, "pdf_theta", *opt_.pdf_theta);
  p.notes = {
      "nu_i(r) = (critical contacts with contact point within r of i's) / (contacts within r), "
      "distance <= r, contact i included unless exclude_self; r in units of the run's mean "
      "diameter D",
      "states: per frame and radius, n = critical contacts with a defined nu_i(r), sum and "
      "sum2 of their nu_i(r); nu_bar = sum/n is eq (3), se = sd/sqrt(n) treats contacts as "
      "independent (correlate pools frames and runs)",
      "edge keep: a neighbourhood is the part of the disk inside the pile; exclude: nu_i(r) "
      "undefined when r exceeds the distance from i to the pile outline",
      "pdf: nu_i at pdf_radius_D of critical (P_c) and non-critical (P_nc) contacts, pooled "
      "over the loading phase (theta <= theta_c of the run) or pdf_theta, and over runs; "
      "bins [k/B, (k+1)/B), 1 in the last",
      "map: nu at grid nodes = critical/contacts within map_radius of the node; NA where no "
      "contact; above = 1 where nu >= map_nu_c"};
  p.results["frames"] = static_cast<std::int64_t>(frames_);
  p.results["pdf_frames"] = pdf_frames_;
  p.results["pdf_critical"] = pc_.total();
  p.results["pdf_noncritical"] = pnc_.total();
  // Lengths: in metres from runs, else in the inputs' own unit, "?" when not known.
  const bool metres = length_unit_ == "m";
  p.parameters["length_unit"] = length_unit_.empty() ? std::string("unknown") : length_unit_;
  for (const auto& [k, v] : map_info_) {
    const bool suffixed = k.size() > 2 && k.compare(k.size() - 2, 2, "_m") == 0;
    p.results[suffixed && !metres ? k.substr(0, k.size() - 2) : k] = v;
  }
  for (const auto& n : extra_notes_) p.notes.push_back(n);
  auto relabel = [&](Table t) {
    for (Column& c : t.columns)
      if (c.unit == "m") c.unit = length_unit_.empty() ? "?" : length_unit_;
    return t;
  };

  p.tables.push_back(relabel(frames_t_));
  p.tables.push_back(states_t_);
  Table& pdf = p.add_table(
      "pdf", "pdfs of nu_i(pdf_radius) over critical (P_c) and non-critical (P_nc) contacts");
  for (auto [nm, u, k] : std::initializer_list<std::tuple<const char*, const char*, ColumnKind>>{
           {"nu", "", ColumnKind::real},
           {"nu_lo", "", ColumnKind::real},
           {"nu_hi", "", ColumnKind::real},
           {"count_c", "", ColumnKind::integer},
           {"count_nc", "", ColumnKind::integer},
           {"P_c", "", ColumnKind::real},
           {"P_nc", "", ColumnKind::real}})
    pdf.add_column(nm, u, k);
  for (std::size_t b = 0; b < pc_.count.size(); ++b) {
    pdf.column("nu").add(pc_.centre(b));
    pdf.column("nu_lo").add(pc_.lo + static_cast<double>(b) * pc_.width());
    pdf.column("nu_hi").add(pc_.lo + static_cast<double>(b + 1) * pc_.width());
    pdf.column("count_c").add_int(pc_.count[b]);
    pdf.column("count_nc").add_int(pnc_.count[b]);
    // an empty pdf is missing, not zero
    pdf.column("P_c").add(pc_.total() ? std::optional<double>(pc_.density(b)) : std::nullopt);
    pdf.column("P_nc").add(pnc_.total() ? std::optional<double>(pnc_.density(b)) : std::nullopt);
  }
  if (mapped_) p.tables.push_back(relabel(map_t_));
  if (mapped_ && opt_.per_contact) p.tables.push_back(relabel(contacts_t_));
  return p;
}

}  // namespace cdpile::analysis
