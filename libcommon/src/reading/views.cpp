#include "cdpile/reading/views.hpp"

#include "cdpile/analysis/critical.hpp"
#include "cdpile/analysis/frame_fields.hpp"
#include "cdpile/reading/inputs.hpp"

namespace cdpile::reading {

RunView run_view(const io::RunHeader& h, const ViewOptions& opt, const std::string& file) {
  RunView v;
  v.mu = run_friction(h, opt.mu, file);
  v.rule = analysis::view_rule(opt.eps, opt.walls, recorded_rule(h, file), v.mu);
  v.nu_radius = opt.nu_radius;
  return v;
}

io::xdmf::Derived xdmf_fields(const io::RunReader& run, const RunView& view) {
  const double diameter = analysis::mean_diameter(run.grain_properties());  // [m]
  const double nu_radius = view.nu_radius * diameter;                       // [m]
  io::xdmf::Derived d;
  d.diameter = diameter;
  d.nu_radius = view.nu_radius;
  d.fields = [view, nu_radius](const Frame& fr) {
    return analysis::frame_fields(fr.contacts, fr.grains, view.mu, view.rule, nu_radius);
  };
  return d;
}

io::lammps::IsCritical lammps_flags(const RunView& view) {
  return [mu = view.mu.grain, eps = view.rule.eps](double fn, double ft) {
    return analysis::is_critical(fn, ft, mu, eps);
  };
}

}  // namespace cdpile::reading
