// cli-demo: a test fixture for the CLI layer and the schema (not installed).
// It declares one option of each kind, and it reads or writes a small pile file, so
// the tool tests can check parsing, help, errors, pipes and atomic output end to end.
#include "cdpile/cli/command.hpp"
#include "cdpile/io/sample.hpp"
#include "cdpile/io/schema.hpp"

#include <iostream>

using namespace cdpile;

static void usage(cli::Usage& u) {
  u.synopsis = "test fixture: parse every kind of option; write or read a small pile file";
  u.description = {
      "Without INPUT, writes a sample pile of --count grains to -o. With INPUT "
      "(a pile or run file, '-' for stdin), validates it and prints a one-line "
      "summary, or copies it to -o."};
  u.argument("input", "pile or run file to read ('-' for standard input)", false, false);
  u.output("output file ('-' for standard output)");
  u.integer("count", 4, "number of grains of the sample pile", 1, 100000);
  u.real("scale", 1e-3, "mean diameter of the sample grains", "m", 1e-9, 1e3);
  u.real_list("radii", "1:1:3", "a list of radii", "D", 0, 100);
  u.text("mode", "summary", "what to print", {"summary", "args"});
  u.text_opt("label", "an optional label");
  u.flag("loud", "a flag", 'l');
  u.seed();
  u.example("Write a sample pile and read it back through a pipe",
            "cli-demo --count 10 -o - | cli-demo -", "prints 'grains 10 frames 1 contacts ...'");
}

static void run(const cli::Args& a) {
  if (a.text("mode") == "args") {
    std::cout << "count=" << a.integer("count") << "\nscale=" << a.real("scale") << "\nradii=";
    for (double r : a.real_list("radii")) std::cout << r << ",";
    std::cout << "\nlabel=" << a.text("label") << "\nloud=" << a.flag("loud")
              << "\nseed=" << a.seed() << "\noutput=" << a.output()
              << "\ninput=" << a.argument("input") << "\n";
    return;
  }
  const std::string in = a.argument("input");
  if (in.empty()) {
    io::Output out(a.output(), a.force());
    io::write_sample_pile(out.create_hdf5(), static_cast<std::size_t>(a.integer("count")),
                          a.real("scale"), a.seed(),
                          io::provenance_now(a.tool(), a.command_line(), ""));
    out.commit();
    return;
  }
  io::Input input(in);
  io::RunReader r(input.hdf5());
  std::size_t contacts = 0;
  for (std::size_t k = 0; k < r.frame_count(); ++k) contacts += r.frame(k).contacts.size();
  if (a.output().empty()) {
    std::cout << "grains " << r.grain_count() << " frames " << r.frame_count() << " contacts "
              << contacts << "\n";
    return;
  }
  io::Output out(a.output(), a.force());
  io::RunHeader h = r.header();
  h.provenance.push_back(io::provenance_now(a.tool(), a.command_line(), input.name()));
  io::RunWriter w(out.create_hdf5(), h, r.grain_properties());
  for (std::size_t k = 0; k < r.frame_count(); ++k) w.append_frame(r.frame(k));
  w.append_series(r.series());
  out.commit();
}

CDPILE_TOOL(usage, run)
