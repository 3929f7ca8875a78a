/// What the views of a run (to-xdmf, to-lammps) show of its contacts, decided here and
/// handed to io as flags and fields: io writes the views, analysis decides which contact is
/// critical (docs/architecture.md, "The layers"). The rule is chosen in one place,
/// analysis::view_rule on the run's recorded rule (docs/analysis.md, "Seeing the grains").
#pragma once

#include "cdpile/analysis/run_record.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/io/xdmf.hpp"

#include <optional>
#include <string>

namespace cdpile::reading {

/// The options of a view: the critical tolerance, friction and wall rule given (each
/// defaulting to the run's recorded ones), and the radius of the grains' local state nu.
struct ViewOptions {
  std::optional<double> eps;    ///< critical tolerance; default the run's critical_eps, else 1e-3
  analysis::FrictionChoice mu;  ///< friction given (analysis::choose_friction on the run's)
  bool walls = false;           ///< nu counts wall contacts too (critical's --walls)
  double nu_radius = 6.0;       ///< [D] radius of the grains' local state nu
};

/// The rule and friction a view of the run with header `h` (file `file`) flags by.
struct RunView {
  analysis::Friction mu;
  analysis::CriticalRule rule;
  double nu_radius = 6.0;  ///< [D]
};
RunView run_view(const io::RunHeader& h, const ViewOptions& opt, const std::string& file);

/// to-xdmf's derived fields of a run's frames: analysis::frame_fields by the view's rule,
/// nu within nu_radius mean diameters of the run's grains.
io::xdmf::Derived xdmf_fields(const io::RunReader& run, const RunView& view);

/// to-lammps --contacts' flag of a grain-grain contact: analysis::is_critical with mu_grain
/// and the view's eps.
io::lammps::IsCritical lammps_flags(const RunView& view);

}  // namespace cdpile::reading
