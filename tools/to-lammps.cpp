// to-lammps: a pile or run as a LAMMPS dump, one snapshot per frame, for OVITO and VMD
// (docs/analysis.md, "Seeing the grains"). The work is in libcommon (io/lammps.hpp).
#include "cdpile/cli/command.hpp"
#include "cdpile/io/checkpoint.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/reading/views.hpp"

#include <optional>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.writes_hdf5 = false;
  u.synopsis = "a pile or run as a LAMMPS dump (one snapshot per frame) for OVITO and VMD";
  u.description = {
      "Writes every frame of a pile or run (HDF5; '-' for standard input) as a snapshot of a "
      "LAMMPS "
      "'dump custom' text file, which OVITO and VMD open as a LAMMPS trajectory (OVITO: File > "
      "Load "
      "File; VMD: mol new FILE type lammpstrj). Columns: id type x y z radius vx vy vz omegaz "
      "mass, "
      "with id = the grain's index + 1, type = 1 for a free grain and 2 for a grain glued to the "
      "floor, z = vz = 0, omegaz the angular velocity (rad/s, counter-clockwise), mass per unit "
      "thickness (kg/m). TIMESTEP is the frame's step. The box bounds are the cdpile box in x (0 "
      "to its width, 'ff'), in y the floor to the top of the highest grain of the frame ('ff'), "
      "and "
      "in z one largest diameter ('pp').",
      "--contacts FILE also writes the same frames' contacts between grains as a LAMMPS 'dump "
      "local' (ITEM: ENTRIES id1 id2 fn ft critical; one snapshot per frame, same TIMESTEP and "
      "box): the force network as bonds for OVITO's Load trajectory modifier. fn >= 0 and ft "
      "(signed, along the contact's tangent) in N/m, critical 1 when |ft| >= (1 - eps) mu fn with "
      "fn > 0, by the run's critical_eps and mu_grain. Wall contacts are left out: a bond needs "
      "two "
      "atoms.",
      "Omitted, because the format has no place for them: the wall contacts, the orientation "
      "(rotation angle) of the grains, the time and the tilt angle of each frame, the walls as "
      "objects (only the box bounds), and every parameter, result and provenance entry of the "
      "file. Units are cdpile's SI (LAMMPS 'units si' in 2D)."};
  u.argument("run",
             "pile or run (HDF5; '-' for standard input); a run tilt-cd is still computing: "
             "OUTPUT.partial, or OUTPUT while only the partial exists");
  u.output("output dump (text; '-' for standard output)", "-");
  u.integer_opt("first", "first frame written (0-based)", 0, INT64_MAX);
  u.integer_opt("last", "last frame written (0-based, inclusive)", 0, INT64_MAX);
  u.integer("every", 1, "write every this many frames", 1, INT64_MAX);
  u.text_opt("contacts", "also write the contacts between grains as a dump local to this file");
  u.example("A run for OVITO", "to-lammps run.h5 -o run.dump", "then open run.dump in OVITO");
  u.example("Grains and force network for OVITO",
            "to-lammps run.h5 -o run.dump --contacts run.contacts.dump",
            "open run.dump, then add a Load trajectory modifier with run.contacts.dump "
            "(docs/analysis.md)");
  u.example("The last frame only", "to-lammps run.h5 --first 40 --last 40 -o end.dump",
            "one snapshot");
}

static void run(const cli::Args& a) {
  io::Output out(a.output(), a.force());  // refuse a bad target before the work
  std::optional<io::Output> contacts;
  if (a.given("contacts")) {
    cli::refuse_output_named_twice(a, "contacts");
    contacts.emplace(a.text("contacts"), a.force());
  }
  io::Input in(io::run_or_partial(a.argument("run")));  // a run still computed: its partial
  const io::RunReader r(in.hdf5());
  io::lammps::ExportOptions opt;
  if (auto v = a.integer_opt("first")) opt.first = static_cast<std::size_t>(*v);
  if (auto v = a.integer_opt("last")) opt.last = static_cast<std::size_t>(*v);
  opt.every = static_cast<std::size_t>(a.integer("every"));
  if (opt.first && opt.last && *opt.first > *opt.last) throw UsageError("--first is after --last");
  if (opt.first && *opt.first >= r.frame_count())
    throw Error(in.name(), "",
                "no frame " + std::to_string(*opt.first) + " (" + std::to_string(r.frame_count()) +
                    " frames)");
  const std::size_t n = io::lammps::write_dump(out.text(), r, opt);
  if (contacts) {
    const reading::RunView view = reading::run_view(r.header(), {}, in.name());
    io::lammps::write_contacts_dump(contacts->text(), r, opt, reading::lammps_flags(view));
  }
  // said once the run has been read: a file that is refused gets its one line, not a note
  if (const std::string note = io::partial_run_note(r); !note.empty()) cli::warn(note);
  out.commit();
  if (contacts) contacts->commit();
  cli::info(std::to_string(n) + " snapshots of " + std::to_string(r.grain_count()) + " grains -> " +
            out.name());
}

CDPILE_TOOL(usage, run)
