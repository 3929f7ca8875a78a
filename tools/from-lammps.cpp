// from-lammps: the contacts of a LAMMPS or LIGGGHTS run as the contact table that localnu
// reads (docs/analysis.md, "Other codes"). The work is in libcommon (io/lammps.hpp).
#include "cdpile/cli/command.hpp"
#include "cdpile/io/files.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/io/products.hpp"

#include <algorithm>

using namespace cdpile;
namespace lmp = cdpile::io::lammps;

static void usage(cli::Usage& u) {
  u.writes_hdf5 = false;
  u.synopsis = "a LAMMPS or LIGGGHTS run's contacts as a contact table for localnu";
  u.description = {
      "Reads text dumps of a LAMMPS or LIGGGHTS run and writes the contact table that localnu "
      "reads "
      "(docs/analysis.md, \"The contact table\"): one row per contact with the frame (the LAMMPS "
      "step), theta, the atom ids i and j (j < 0 a wall: -1 floor, -2 left, -3 right, -4 top, -5 "
      "another wall), wall, the contact point x y, fn and ft. Give every dump file, in any order: "
      "atoms snapshots (dump custom, ITEM: ATOMS) and contact snapshots (dump local, ITEM: "
      "ENTRIES) are matched by their TIMESTEP, whether each file holds one snapshot or many.",
      "Atoms (dump custom): id, x y (or xu yu, xs ys), radius (or diameter); mass fx fy for "
      "--check; for the walls of 'fix ID ... wall/gran ... contacts', its per-atom columns f_ID[1] "
      "(in contact), f_ID[2] f_ID[3] (the wall's force on the atom) and, if dumped, f_ID[5] "
      "f_ID[6] "
      "(the contact point). Contacts (dump local): LAMMPS 'compute property/local patom1 patom2' "
      "with 'compute pair/local' (force = fn, fx fy = the normal force on atom 1, and for granular "
      "pair styles p1 p2 = the tangential force on atom 1, p4 = its magnitude); LIGGGHTS 'compute "
      "pair/gran/local' (id, pos, force, force_normal, force_tangential) and 'compute "
      "wall/gran/local' for mesh walls.",
      "Columns are found by name, in any order. A dump local names them c_ID[k]: their meaning "
      "comes "
      "from the compute commands of the input script (--script, which also gives the wall fixes, "
      "the pair style and the units), or is given with --columns NAME=ROLE, or the header already "
      "uses the role names: id1 id2 fn fnx fny ftx fty ftmag fx fy x1 y1 x2 y2 px py wall. Unknown "
      "columns are ignored. The contact point of a pair is x_j + n (r_j - h/2) with n the unit "
      "vector from j to i and h the overlap; of a wall contact, the dumped point, else the atom's "
      "foot on the plane at one radius. fn = F.n and ft = F.t with t = (-n_y, n_x), F the contact "
      "force on i; with only |f_t| in the dump (p4), ft is unsigned.",
      "theta: rate x dt x step with --rate (deg per time unit) and --dt (else the script's numeric "
      "timestep, else the dump's TIME), or the atoms column --theta-column; without either the "
      "table has no theta. --check rebuilds every atom's total force from the table's rows (fn n + "
      "ft t over its contacts, the opposite on the other atom) plus m g (sin theta, -cos theta) "
      "and "
      "compares it with the dump's fx fy: it fails (exit 1, no table) when they differ by more "
      "than --check-tolerance m g for any atom, and reports the largest difference. A pair given "
      "twice in a snapshot (newton off on several ranks) is an error naming both lines, or with "
      "--duplicates merge is counted once.",
      "The table declares its length unit ('# length_unit: m' for 'units si'), so localnu labels "
      "its "
      "lengths. Output: TSV on standard output, or -o FILE."};
  u.argument("dumps",
             "dump files (atoms and contacts, one or many snapshots each; '-' for standard input)",
             true);
  u.output("output contact table (TSV; '-' for standard output)", "-");
  u.group("What the columns are");
  u.text_opt(
      "script",
      "LAMMPS or LIGGGHTS input script(s), comma-separated: compute, fix wall/gran, pair_style, "
      "units, timestep and include commands are read");
  u.text_opt("pair-style",
             "the pair style, when the script does not set it (read_restart): the meaning of "
             "pair/local's p1 p2 p4 (tangential force for the gran and granular styles)");
  u.text_opt(
      "columns",
      "roles of dump local columns, comma-separated NAME=ROLE (e.g. 'c_cpl[2]=fn,c_cpl[7]=ftmag')");
  u.text_opt("wall",
             "wall fixes with per-atom contact columns, comma-separated FIX=AXIS (x or y: the "
             "plane's normal), "
             "e.g. 'floor=y,sides=x' (the script gives them too)");
  u.group("Tilt");
  u.real_opt("rate", "tilt rate: theta = rate x dt x step", "deg per time unit");
  u.real_opt("dt", "time step of the run (default: the script's timestep)", "time unit", 1e-300,
             1e300);
  u.text_opt("theta-column",
             "an atoms column holding the tilt angle in degrees (the same for every atom)");
  u.group("Checks");
  u.text("duplicates", "error", "a pair given twice in one snapshot", {"error", "merge"});
  u.flag("check",
         "compare every atom's force rebuilt from the table (plus m g) with the dump's fx fy");
  u.real("gravity", 9.81, "g for --check, in the run's units", "", 0, 1e300);
  u.real("check-tolerance", 1e-3,
         "largest difference --check accepts (compute pair/local re-evaluates a granular "
         "pair's damping with end-of-step velocities: on tilted LAMMPS piles its forces and the "
         "atoms' fx fy differ "
         "by 1e-8 to 2e-4 m g, docs/performance.md)",
         "m g", 0, 1e300);
  u.example("The dumps of benchmarks/peers/lammps/in.contactdump",
            "from-lammps atoms_*.txt contacts_*.txt --script in.tilt --pair-style "
            "gran/hooke/history --rate 10 --dt 1e-5 "
            "--check -o contacts.tsv",
            "in.tilt includes in.contactdump (computes cpl, cpp and the wall fixes floor, sides) "
            "and reads its pair "
            "style from a restart; every snapshot is a frame; then: localnu contacts.tsv --mu 0.5 "
            "--diameter 0.001");
  u.example("Without a script",
            "from-lammps atoms.dump pairs.dump --columns "
            "'c_p[1]=id1,c_p[2]=id2,c_f[1]=fn,c_f[2]=ftx,c_f[3]=fty'",
            "names the role of each contact column by hand");
  u.example("Straight into localnu",
            "from-lammps run.dump pairs.dump --script in.run | localnu - --mu 0.5 --diameter 0.001",
            "the table goes through a pipe");
}

static void run(const cli::Args& a) {
  lmp::ConvertOptions opt;
  for (const std::string& path : cli::split_list(a.text("script")))
    lmp::read_script(path, opt.script);
  if (a.given("pair-style")) opt.script.pair_style = a.text("pair-style");
  for (const std::string& item : cli::split_list(a.text("columns"))) {
    const auto eq = item.rfind('=');
    if (eq == std::string::npos || eq == 0)
      throw UsageError("--columns: expected NAME=ROLE, got '" + item + "'");
    const std::string role = item.substr(eq + 1);
    const auto& roles = lmp::entry_roles();
    if (role != "ignore" && std::find(roles.begin(), roles.end(), role) == roles.end()) {
      std::string list;
      for (const auto& r : roles) list += " " + r;
      throw UsageError("--columns: unknown role '" + role + "' (roles:" + list + ", ignore)");
    }
    opt.columns[item.substr(0, eq)] = role == "ignore" ? "" : role;
  }
  for (const std::string& item : cli::split_list(a.text("wall"))) {
    const auto eq = item.rfind('=');
    const std::string axis = eq == std::string::npos ? "" : item.substr(eq + 1);
    if (eq == std::string::npos || eq == 0 || (axis != "x" && axis != "y"))
      throw UsageError("--wall: expected FIX=x or FIX=y, got '" + item + "'");
    opt.wall_axes[item.substr(0, eq)] = axis[0];
  }
  opt.rate = a.real_opt("rate");
  opt.dt = a.real_opt("dt");
  opt.theta_column = a.text("theta-column");
  if (opt.rate && !opt.theta_column.empty())
    throw UsageError("--rate and --theta-column exclude each other");
  if (opt.dt && !opt.rate) throw UsageError("--dt without --rate");
  opt.duplicates = a.text("duplicates") == "merge" ? io::Duplicates::merge : io::Duplicates::error;
  opt.check = a.flag("check");
  opt.gravity = a.real("gravity");
  opt.check_tolerance = a.real("check-tolerance");
  const auto& paths = a.arguments("dumps");
  if (std::count(paths.begin(), paths.end(), "-") > 1)
    throw UsageError("'-' (standard input) given twice");

  io::Output out(a.output(), a.force());  // refuse a bad target before the work
  std::vector<lmp::TextFile> dumps;
  for (const std::string& p : paths) {
    const std::vector<char> bytes = io::read_all(p);
    dumps.push_back({p == "-" ? "stdin" : p, std::string(bytes.begin(), bytes.end())});
  }
  const lmp::Conversion c = lmp::convert(dumps, opt);
  lmp::write_table(out.text(), c, {"from-lammps " CDPILE_VERSION ": " + a.command_line()});
  out.commit();
  cli::info(std::to_string(c.frames) + " frames, " + std::to_string(c.pair_rows) + " pair and " +
            std::to_string(c.wall_rows) + " wall contact rows" +
            (c.merged ? ", " + std::to_string(c.merged) + " repeats merged" : "") + " -> " +
            out.name());
  if (opt.check && !c.checks.empty()) {
    double free = 0, all = 0;
    for (const auto& f : c.checks) {
      free = std::max(free, f.worst_free);
      all = std::max(all, f.worst_all);
    }
    char line[256];
    std::snprintf(line, sizeof line,
                  "check: worst |table forces + m g - LAMMPS f|/(m g) = %.2e off the walls, %.2e "
                  "all grains (%zu frames)",
                  free, all, c.checks.size());
    cli::info(line);
  }
}

CDPILE_TOOL(usage, run)
