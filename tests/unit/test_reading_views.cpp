// What to-xdmf and to-lammps --contacts write for viewers, as the tools call them: the view's
// rule and fields from reading/views.hpp, written by io/xdmf.hpp and io/lammps.hpp. On a run of
// three grains in a row whose contacts are known (three_in_a_row.hpp): (0, 1) critical
// (|f_t| = mu f_n), (1, 2) not, (2, floor) a wall contact. The network's segments join the
// centres of the pair (the contact point for the wall), f_n / <f_n> is 2/2, 1/2, 3/2, the XDMF
// names no hyperslab (ParaView's Xdmf3 reader crashes on one), and the dump local holds the
// two pairs alone.
#include "cdpile/io/h5.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/io/xdmf.hpp"
#include "cdpile/reading/views.hpp"
#include "scratch_dir.hpp"
#include "three_in_a_row.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <unistd.h>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace cdpile;
namespace h5 = cdpile::io::h5;

using test::three_in_a_row;

TEST(Views, TheNetworkJoinsTheCentresOfEachPairWithItsForceOverTheMean) {
  const ScratchDir s("views");
  three_in_a_row((s.dir / "run.h5").string());
  const h5::File run = h5::open_read((s.dir / "run.h5").string(), "run.h5");
  const io::RunReader r(run);
  std::ostringstream grains, network;
  io::xdmf::Summary sum;
  {
    h5::File side = h5::create((s.dir / "run.xdmf.hdf5").string(), "run.xdmf.hdf5");
    const reading::RunView view = reading::run_view(r.header(), {}, "run.h5");
    sum = io::xdmf::write_run(grains, network, side, r, "run.h5", "run.xdmf.hdf5",
                              reading::xdmf_fields(r, view));
    side.close();
  }
  EXPECT_EQ(sum.grains, 3u);
  EXPECT_EQ(sum.contacts, 3u);
  EXPECT_NEAR(sum.tilt_last_deg, 0.1 * 180 / M_PI, 1e-12);  // the file's degrees
  const h5::File side = h5::open_read((s.dir / "run.xdmf.hdf5").string(), "run.xdmf.hdf5");
  EXPECT_EQ(h5::read<std::int32_t>(side, "/frames/0/network/lines", {3, 2}),
            (std::vector<std::int32_t>{1, 0, 2, 1, 2, 3 + 2}));  // the wall: point N + q
  const auto points = h5::read<double>(side, "/frames/0/network/points", {6, 2});
  EXPECT_EQ(points[2 * 5], 0.005);  // the wall contact's point, read in place from the run
  EXPECT_EQ(points[2 * 5 + 1], 0.0);
  EXPECT_EQ(points[2 * 1], 0.001 + 0.002 * 1);  // grain 1's centre
  EXPECT_EQ(h5::read<double>(side, "/frames/0/contacts/fn_rel", {3}),
            (std::vector<double>{1.0, 0.5, 1.5}));
  EXPECT_EQ(h5::read<std::uint8_t>(side, "/frames/0/contacts/critical", {3}),
            (std::vector<std::uint8_t>{1, 0, 0}));
  EXPECT_EQ(h5::read<double>(side, "/frames/0/velocity", {3, 3}), std::vector<double>(9, 0.0));
  // no hyperslab, no function; the network's cells are segments
  for (const std::string& x : {grains.str(), network.str()}) {
    EXPECT_EQ(x.find("HyperSlab"), std::string::npos);
    EXPECT_EQ(x.find("Function"), std::string::npos);
  }
  EXPECT_NE(
      network.str().find(
          "<Topology TopologyType=\"Polyline\" NumberOfElements=\"3\" NodesPerElement=\"2\">"),
      std::string::npos);
  EXPECT_NE(grains.str().find("<Time Value=\"0.004\"/>"), std::string::npos);
  // the state draws what is described, on the run's ranges
  const std::string state = io::xdmf::paraview_state(sum, "run.xdmf", "/x/run.xdmf",
                                                     "run.network.xdmf", "/x/run.network.xdmf");
  EXPECT_NE(state.find("red.AmbientColor = red.DiffuseColor = [0.9, 0.0, 0.0]"), std::string::npos);
  EXPECT_NE(state.find("tilt.Expression = \"'tilt %.2f deg' % tilt_angle[0]\""), std::string::npos);
  // the network's colour range: to the 99th percentile of f_n / <f_n>, here the middle one
  EXPECT_NE(state.find("fn_lut.RGBPoints = [0.0, 0.6, 0.6, 0.6, 1, 0.0, 0.0, 0.0]"),
            std::string::npos);
}

TEST(Views, TheContactsDumpHoldsThePairsWithTheirForcesAndFlags) {
  const ScratchDir s("views");
  three_in_a_row((s.dir / "run.h5").string());
  const h5::File run = h5::open_read((s.dir / "run.h5").string(), "run.h5");
  const io::RunReader r(run);
  std::ostringstream os;
  const reading::RunView view = reading::run_view(r.header(), {}, "run.h5");
  EXPECT_EQ(io::lammps::write_contacts_dump(os, r, {}, reading::lammps_flags(view)), 1u);
  const std::string text = os.str();
  EXPECT_EQ(text.substr(0, text.find("ITEM: BOX")),
            "ITEM: TIMESTEP\n40\nITEM: NUMBER OF ENTRIES\n2\n");
  EXPECT_EQ(text.substr(text.find("ITEM: ENTRIES")),
            "ITEM: ENTRIES id1 id2 fn ft critical\n2 1 2 1 1\n3 2 1 0.1 0\n");
}

// The view's rule is decided in one place (analysis::view_rule through run_view): the run's
// recorded eps and mu unless given, and the flags follow it.
TEST(Views, TheRuleIsTheRunsRecordedOneUnlessGiven) {
  const ScratchDir s("views");
  three_in_a_row((s.dir / "run.h5").string());
  const h5::File run = h5::open_read((s.dir / "run.h5").string(), "run.h5");
  const io::RunReader r(run);
  const reading::RunView recorded = reading::run_view(r.header(), {}, "run.h5");
  EXPECT_EQ(recorded.rule.eps, 1e-3);
  EXPECT_EQ(recorded.mu.grain, 0.5);
  // |f_t| = 0.4985 f_n: critical within eps 1e-2 of mu 0.5 ((1 - 1e-2) 0.5 = 0.495), not
  // within the recorded 1e-3 (0.4995)
  EXPECT_FALSE(reading::lammps_flags(recorded)(1.0, 0.4985));
  reading::ViewOptions wide;
  wide.eps = 1e-2;
  EXPECT_TRUE(reading::lammps_flags(reading::run_view(r.header(), wide, "run.h5"))(1.0, -0.4985));
  reading::ViewOptions lower_mu;
  lower_mu.mu.grain = 0.1;  // the pair (1, 2): f_t = 0.1 f_n, critical at mu = 0.1
  const io::xdmf::Derived d =
      reading::xdmf_fields(r, reading::run_view(r.header(), lower_mu, "run.h5"));
  EXPECT_EQ(d.diameter, 0.002);
  EXPECT_EQ(d.fields(r.frame(0)).critical, (std::vector<std::uint8_t>{1, 1, 0}));
}
