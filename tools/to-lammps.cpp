// to-lammps: a pile or run as a LAMMPS dump, one snapshot per frame, for OVITO and VMD
// (docs/analysis.md, "Seeing the grains"). The work is in libcommon (io/lammps.hpp).
#include "cdpile/cli/command.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/lammps.hpp"

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
      "Omitted, because the format has no place for them: the contacts and their forces (see "
      "to-xdmf for those), the orientation (rotation angle) of the grains, the time and the tilt "
      "angle of each frame, the walls as objects (only the box bounds), and every parameter, "
      "result and provenance entry of the file. Units are cdpile's SI (LAMMPS 'units si' in 2D)."};
  u.argument("run", "pile or run (HDF5; '-' for standard input)");
  u.output("output dump (text; '-' for standard output)", "-");
  u.integer_opt("first", "first frame written (0-based)", 0, INT64_MAX);
  u.integer_opt("last", "last frame written (0-based, inclusive)", 0, INT64_MAX);
  u.integer("every", 1, "write every this many frames", 1, INT64_MAX);
  u.example("A run for OVITO", "to-lammps run.h5 -o run.dump", "then open run.dump in OVITO");
  u.example("The last frame only", "to-lammps run.h5 --first 40 --last 40 -o end.dump",
            "one snapshot");
}

static void run(const cli::Args& a) {
  io::Output out(a.output(), a.force());  // refuse a bad target before the work
  io::Input in(a.argument("run"));
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
  out.commit();
  cli::info(std::to_string(n) + " snapshots of " + std::to_string(r.grain_count()) + " grains -> " +
            out.name());
}

CDPILE_TOOL(usage, run)
