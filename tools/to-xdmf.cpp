// to-xdmf: an XDMF description of a pile, run or localnu map, so that ParaView opens it
// (docs/analysis.md, "Seeing the grains"). The work is in libcommon (io/xdmf.hpp).
#include "cdpile/analysis/critical_option.hpp"
#include "cdpile/cli/command.hpp"
#include "cdpile/cli/friction_options.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/xdmf.hpp"
#include "cdpile/reading/views.hpp"

#include <filesystem>
#include <optional>

using namespace cdpile;
namespace fs = std::filesystem;

static void usage(cli::Usage& u) {
  u.writes_hdf5 = false;
  u.synopsis = "an XDMF description of a pile, run or localnu map, for ParaView";
  u.description = {
      "Writes XDMF files that ParaView opens with File > Open (its Xdmf3 reader, or the legacy "
      "'XDMF Reader'): they refer to arrays read in place, not copied. Keep the files together: "
      "the XDMF names the input by its path relative to itself.",
      "A pile or run gives OUTPUT, the grains: every frame (the time slider runs over the frames, "
      "Time in s) as one point per grain centre with radius, species, mass, velocity (a 3-vector "
      "with z = 0), angular_velocity, orientation and nu, and the frame's tilt_angle and step as "
      "field data; and STEM.network.xdmf, what is drawn over them: contacts, the force network as "
      "one segment per contact between the centres of the two grains (to the contact point for a "
      "wall) with i, j, fn, ft, gap, status, normal, point, fn_rel = fn / the frame's mean fn, "
      "critical (1 when |f_t| >= (1 - eps) mu f_n, f_n > 0, with the run's critical_eps, "
      "mu_grain and mu_wall unless --eps, --mu, --mu-wall) and mobilisation |f_t| / (mu f_n); "
      "gravity, an arrow above the pile that turns with the tilt (the box's frame); walls. nu of "
      "a grain is the local state at its centre: critical contacts / contacts within "
      "--nu-radius mean diameters, counting the contacts critical counts (between free grains; "
      "with --walls all), as localnu's map does at its grid nodes; NaN where no contact is within "
      "reach.",
      "A localnu product (HDF5, with its map) gives the nu field of the mapped frame on its grid: "
      "nu, above (nu >= nu_c), contacts and critical at each node; NaN where the map has no value.",
      "Also written: OUTPUT.hdf5, every frame's arrays as whole datasets (ParaView's Xdmf3 reader "
      "reads no hyperslab): virtual datasets (HDF5 1.10) reading the input's rows in place, and "
      "what the input does not hold (critical, mobilisation, fn_rel, nu, the network's segments; "
      "a map with NaN); and STEM.paraview.py, a ParaView state: File > Load State... that file "
      "(or paraview --state=STEM.paraview.py) shows the disks at their radius coloured by nu on "
      "the run's range, the force network grey to black by fn / <fn> with the critical contacts "
      "in red, gravity, the walls and the tilt angle of the frame shown.",
      "A run still being computed: give tilt-cd's OUTPUT.partial (or OUTPUT while only the "
      "partial exists); the views show its frames up to its last checkpoint, and refer to the "
      "partial by name, so run to-xdmf again on the finished run."};
  u.argument("input",
             "pile, run or localnu product (HDF5 file; not standard input: the XDMF refers to it "
             "by name); a run tilt-cd is still computing: OUTPUT.partial, or OUTPUT while only "
             "the partial exists");
  u.output("output XDMF file (default: INPUT with the extension .xdmf)");
  u.real("nu-radius", 6.0, "radius of the grains' local state nu", "D", 1e-6, 1e6);
  u.declare(analysis::eps_option("Options", analysis::EpsDefault::from_run));
  cli::declare_friction(u, "grain-grain friction coefficient (default: the run's mu_grain)",
                        "grain-wall friction coefficient (default: the run's mu_wall)");
  u.flag("walls", "nu counts the contacts with walls and glued floor grains too");
  u.example("A run for ParaView", "to-xdmf run.h5",
            "writes run.xdmf, run.xdmf.hdf5 and run.paraview.py; in ParaView: File > Load "
            "State..., run.paraview.py");
  u.example("The nu field of a localnu map", "localnu run.h5 -o nu.h5 && to-xdmf nu.h5",
            "writes nu.xdmf and the rest");
}

static void run(const cli::Args& a) {
  // a run tilt-cd is still computing: its partial
  const std::string input = io::run_or_partial(a.argument("input"));
  if (input == "-")
    throw UsageError("the input must be a file: an XDMF file refers to its data by file name");
  std::string output = a.output();
  if (output == "-")
    throw UsageError("-o -: an XDMF file goes beside its data, not to standard output");
  if (output.empty()) output = fs::path(input).replace_extension(".xdmf").string();
  const fs::path out_abs = fs::absolute(output);
  fs::path stem = out_abs;
  if (stem.extension() == ".xdmf" || stem.extension() == ".xmf") stem.replace_extension();
  const std::string sidecar_path =
      output + ".hdf5";  // not .h5: globs of runs (run*.h5) must not take it
  const std::string state_path =
      (fs::path(output).parent_path() / (stem.filename().string() + ".paraview.py")).string();
  const std::string network_path =
      (fs::path(output).parent_path() / (stem.filename().string() + ".network.xdmf")).string();
  if (fs::absolute(input).lexically_normal() == out_abs.lexically_normal() ||
      fs::absolute(input).lexically_normal() == fs::absolute(sidecar_path).lexically_normal())
    throw UsageError("the output would replace the input " + input);

  io::Output xml(output, a.force()), side(sidecar_path, a.force()), state(state_path, a.force());
  io::Input in(input);
  const io::RunHeader header = io::read_header(in.hdf5());
  const bool is_run = header.kind == "pile" || header.kind == "run";
  std::optional<io::Output> network;  // a run's second XDMF: the force network, gravity, walls
  if (is_run) network.emplace(network_path, a.force());
  const std::string data_ref =
      fs::absolute(input).lexically_normal().lexically_relative(out_abs.parent_path()).string();
  const std::string side_ref = fs::path(sidecar_path).filename().string();
  io::xdmf::Summary s;
  if (is_run) {
    reading::ViewOptions opt;
    opt.nu_radius = a.real("nu-radius");
    opt.eps = a.real_opt("eps");
    opt.mu = cli::friction_choice(a);
    opt.walls = a.flag("walls");
    const io::RunReader r(in.hdf5());
    const reading::RunView view = reading::run_view(header, opt, in.name());
    s = io::xdmf::write_run(xml.text(), network->text(), side.create_hdf5(), r, data_ref, side_ref,
                            reading::xdmf_fields(r, view));
    // said once the run has been read: a file that is refused gets its one line, not a note
    if (const std::string note = io::partial_run_note(r); !note.empty())
      cli::warn(note + "; the views name the partial: run to-xdmf again on the finished run");
  } else {
    s = io::xdmf::write_localnu(xml.text(), side.create_hdf5(), in.hdf5(), data_ref, side_ref);
  }
  const fs::path network_abs = fs::absolute(network_path);
  state.text() << io::xdmf::paraview_state(s, out_abs.filename().string(), out_abs.string(),
                                           network_abs.filename().string(), network_abs.string());
  side.commit();
  xml.commit();
  if (network) network->commit();
  state.commit();
  if (s.kind == "localnu")
    cli::info(xml.name() + ": the nu field, " + std::to_string(s.nx) + " x " +
              std::to_string(s.ny) + " nodes; " + side.name() + ", " + state.name());
  else
    cli::info(xml.name() + ": " + std::to_string(s.grains) + " grains, " +
              std::to_string(s.frames) + " frames, " + std::to_string(s.contacts) +
              " contact rows; " + network->name() + ", " + side.name() + ", " + state.name());
}

CDPILE_TOOL(usage, run)
