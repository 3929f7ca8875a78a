// localnu: the local state nu_i(r) of every contact (eq 1 on a disk of radius r), its
// sums over critical contacts per frame (for eq 3), the pdfs P_c and P_nc at one radius
// (Fig 3) and the nu field on a grid (Fig 5).
#include "cdpile/analysis/localnu_study.hpp"

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

// Each table is one list of columns (ColumnSpec, table.hpp); a row type holds what its
// getters read.
using K = ColumnKind;

// --- frames: one row per frame, the state of the pile
struct FrameRow {
  std::int64_t run, frame, step;
  std::optional<double> theta;
  double diameter;
  std::int64_t n, nc;
  bool loading;
};
const ColumnSpec<FrameRow> frame_columns[] = {
    {"run", "", K::integer, [](const FrameRow& x) -> Cell { return x.run; }},
    {"frame", "", K::integer, [](const FrameRow& x) -> Cell { return x.frame; }},
    {"step", "", K::integer, [](const FrameRow& x) -> Cell { return x.step; }},
    {"theta", "deg", K::real, [](const FrameRow& x) -> Cell { return x.theta; }},
    {"diameter", "m", K::real, [](const FrameRow& x) -> Cell { return x.diameter; }},
    {"N", "", K::integer, [](const FrameRow& x) -> Cell { return x.n; }},
    {"Nc", "", K::integer, [](const FrameRow& x) -> Cell { return x.nc; }},
    {"nu", "", K::real,
     [](const FrameRow& x) -> Cell {
       return x.n > 0 ? std::optional<double>(static_cast<double>(x.nc) / static_cast<double>(x.n))
                      : std::nullopt;
     }},
    {"loading", "", K::integer, [](const FrameRow& x) -> Cell { return std::int64_t{x.loading}; }},
};

// --- states: one row per frame and radius, the sums of eq (3) over critical contacts
struct StateRow {
  std::int64_t run, frame;
  std::optional<double> theta;
  double r;  // [D]
  Sums sums;
};
const ColumnSpec<StateRow> state_columns[] = {
    {"run", "", K::integer, [](const StateRow& x) -> Cell { return x.run; }},
    {"frame", "", K::integer, [](const StateRow& x) -> Cell { return x.frame; }},
    {"theta", "deg", K::real, [](const StateRow& x) -> Cell { return x.theta; }},
    {"r", "D", K::real, [](const StateRow& x) -> Cell { return x.r; }},
    {"n", "", K::integer, [](const StateRow& x) -> Cell { return x.sums.n; }},
    {"sum", "", K::real, [](const StateRow& x) -> Cell { return x.sums.sum; }},
    {"sum2", "", K::real, [](const StateRow& x) -> Cell { return x.sums.sum2; }},
    {"nu_bar", "", K::real, [](const StateRow& x) -> Cell { return x.sums.summary().mean; }},
    {"se", "", K::real, [](const StateRow& x) -> Cell { return x.sums.summary().se; }},
};

// --- map: the nu field on a grid over the pile (Fig 5)
struct MapRow {
  const Field& f;
  std::size_t a, b;
  double diameter, nu_c;
  double x() const { return f.x0 + static_cast<double>(a) * f.dx; }
  double y() const { return f.y0 + static_cast<double>(b) * f.dx; }
};
const ColumnSpec<MapRow> map_columns[] = {
    {"ix", "", K::integer, [](const MapRow& m) -> Cell { return static_cast<std::int64_t>(m.a); }},
    {"iy", "", K::integer, [](const MapRow& m) -> Cell { return static_cast<std::int64_t>(m.b); }},
    {"x", "m", K::real, [](const MapRow& m) -> Cell { return m.x(); }},
    {"y", "m", K::real, [](const MapRow& m) -> Cell { return m.y(); }},
    {"x_D", "D", K::real, [](const MapRow& m) -> Cell { return m.x() / m.diameter; }},
    {"y_D", "D", K::real, [](const MapRow& m) -> Cell { return m.y() / m.diameter; }},
    {"contacts", "", K::integer,
     [](const MapRow& m) -> Cell { return std::int64_t{m.f.total[m.b * m.f.nx + m.a]}; }},
    {"critical", "", K::integer,
     [](const MapRow& m) -> Cell { return std::int64_t{m.f.critical[m.b * m.f.nx + m.a]}; }},
    {"nu", "", K::real, [](const MapRow& m) -> Cell { return m.f.nu(m.a, m.b); }},
    {"above", "", K::integer,
     [](const MapRow& m) -> Cell {
       const auto v = m.f.nu(m.a, m.b);
       return v ? std::optional<double>(*v >= m.nu_c ? 1.0 : 0.0) : std::nullopt;
     }},
};

// --- contacts: every contact of the mapped frame; then a column nu_r<r> per radius
struct ContactRow {
  const ContactSet& set;
  std::size_t c;
};
const ColumnSpec<ContactRow> contact_columns[] = {
    {"x", "m", K::real, [](const ContactRow& k) -> Cell { return k.set.point[k.c].x(); }},
    {"y", "m", K::real, [](const ContactRow& k) -> Cell { return k.set.point[k.c].y(); }},
    {"i", "", K::integer, [](const ContactRow& k) -> Cell { return std::int64_t{k.set.i[k.c]}; }},
    {"j", "", K::integer, [](const ContactRow& k) -> Cell { return std::int64_t{k.set.j[k.c]}; }},
    {"critical", "", K::integer,
     [](const ContactRow& k) -> Cell { return std::int64_t{k.set.critical[k.c]}; }},
    // NA, not 0, when the input says nothing about the solver's status
    {"sliding", "", K::integer,
     [](const ContactRow& k) -> Cell {
       return k.set.has_status ? std::optional<double>(k.set.sliding[k.c]) : std::nullopt;
     }},
    {"mobilisation", "", K::real,
     [](const ContactRow& k) -> Cell { return k.set.mobilisation[k.c]; }},
};

// --- pdf: P_c and P_nc of nu_i at the pdf radius (Fig 3)
struct PdfRow {
  const Histogram &pc, &pnc;
  std::size_t b;
};
const ColumnSpec<PdfRow> pdf_columns[] = {
    {"nu", "", K::real, [](const PdfRow& x) -> Cell { return x.pc.centre(x.b); }},
    {"nu_lo", "", K::real,
     [](const PdfRow& x) -> Cell { return x.pc.lo + static_cast<double>(x.b) * x.pc.width(); }},
    {"nu_hi", "", K::real,
     [](const PdfRow& x) -> Cell { return x.pc.lo + static_cast<double>(x.b + 1) * x.pc.width(); }},
    {"count_c", "", K::integer, [](const PdfRow& x) -> Cell { return x.pc.count[x.b]; }},
    {"count_nc", "", K::integer, [](const PdfRow& x) -> Cell { return x.pnc.count[x.b]; }},
    // an empty pdf is missing, not zero
    {"P_c", "", K::real,
     [](const PdfRow& x) -> Cell {
       return x.pc.total() ? std::optional<double>(x.pc.density(x.b)) : std::nullopt;
     }},
    {"P_nc", "", K::real,
     [](const PdfRow& x) -> Cell {
       return x.pnc.total() ? std::optional<double>(x.pnc.density(x.b)) : std::nullopt;
     }},
};

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
  declare_columns(frames_t_, frame_columns);
  states_t_.name = "states";
  states_t_.title =
      "one row per frame and radius: sums of nu_i(r) over the frame's critical contacts";
  declare_columns(states_t_, state_columns);
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
  add_row(frames_t_, frame_columns, FrameRow{run, frame, step, theta, diameter, n, nc, loading});

  const std::vector<Sums> sums = state_sums(s, set.critical, 1);  // eq (3) numerators
  for (std::size_t q = 0; q < opt_.radii.size(); ++q)
    add_row(states_t_, state_columns, StateRow{run, frame, theta, opt_.radii[q], sums[out_k_[q]]});

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
    declare_columns(map_t_, map_columns);
    for (std::size_t b = 0; b < f.ny; ++b)
      for (std::size_t a = 0; a < f.nx; ++a)
        add_row(map_t_, map_columns, MapRow{f, a, b, diameter, opt_.nu_c});
    map_info_["map_nx"] = static_cast<std::int64_t>(f.nx);
    map_info_["map_ny"] = static_cast<std::int64_t>(f.ny);
    map_info_["map_x0_m"] = f.x0;
    map_info_["map_y0_m"] = f.y0;
    map_info_["map_dx_m"] = f.dx;

    if (opt_.per_contact) {
      contacts_t_.name = "contacts";
      contacts_t_.title = "nu_i(r) of every contact of the mapped frame";
      declare_columns(contacts_t_, contact_columns);
      constexpr std::size_t first_radius = std::size(contact_columns);
      for (double r : opt_.radii) contacts_t_.add_column(radius_name(r), "", ColumnKind::real);
      for (std::size_t c = 0; c < set.size(); ++c) {
        add_row(contacts_t_, contact_columns, ContactRow{set, c});
        for (std::size_t q = 0; q < opt_.radii.size(); ++q)
          contacts_t_.columns[first_radius + q].add(s.nu(c, out_k_[q]));
      }
    }
  }
}


void LocalNuStudy::add_summary(std::int64_t run, const Product& s) {
  // A summary's rows as add_frame writes them, nu, nu_bar and se from the counts and sums
  // a summary keeps.
  const Table& frames = s.table("localnu_frames");
  auto number = [&](const Table& t, const char* name) -> const Column& {
    const Column* c = t.find(name);
    if (!c || c->kind == ColumnKind::text)
      throw Error(s.source, "/tables/" + t.name, "no " + std::string(name) + " column of its kind");
    return *c;
  };
  auto integer = [](const Column& c, std::size_t k) { return static_cast<std::int64_t>(c.num[k]); };
  {
    const Column &frame = number(frames, "frame"), &step = number(frames, "step"),
                 &theta = number(frames, "theta"), &diameter = number(frames, "diameter"),
                 &n = number(frames, "N"), &nc = number(frames, "Nc"),
                 &loading = number(frames, "loading");
    for (std::size_t k = 0; k < frames.rows(); ++k)
      add_row(frames_t_, frame_columns,
          FrameRow{run, integer(frame, k), integer(step, k), theta.get(k), diameter.num[k],
                   integer(n, k), integer(nc, k), loading.num[k] != 0.0});
  }
  const Table& states = s.table("localnu_states");
  {
    const Column &frame = number(states, "frame"), &theta = number(states, "theta"),
                 &r = number(states, "r"), &n = number(states, "n"), &sum = number(states, "sum"),
                 &sum2 = number(states, "sum2");
    for (std::size_t k = 0; k < states.rows(); ++k)
      add_row(states_t_, state_columns,
          StateRow{run, integer(frame, k), theta.get(k), r.num[k],
                   Sums{integer(n, k), sum.num[k], sum2.num[k]}});
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
  declare_columns(pdf, pdf_columns);
  for (std::size_t b = 0; b < pc_.count.size(); ++b) add_row(pdf, pdf_columns, PdfRow{pc_, pnc_, b});
  if (mapped_) p.tables.push_back(relabel(map_t_));
  if (mapped_ && opt_.per_contact) p.tables.push_back(relabel(contacts_t_));
  return p;
}

}  // namespace cdpile::analysis
