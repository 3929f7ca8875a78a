// What to-xdmf and to-lammps --contacts write for viewers (io/xdmf.hpp, io/lammps.hpp), on a
// run of three grains in a row whose contacts are known: (0, 1) critical (|f_t| = mu f_n),
// (1, 2) not, (2, floor) a wall contact. The network's segments join the centres of the pair
// (the contact point for the wall), f_n / <f_n> is 2/2, 1/2, 3/2, the XDMF names no hyperslab
// (ParaView's Xdmf3 reader crashes on one), and the dump local holds the two pairs alone.
#include "scratch_dir.hpp"
#include "cdpile/io/h5.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/io/schema.hpp"
#include "cdpile/io/xdmf.hpp"

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

namespace {


/// The run, written to `path`.
void three_in_a_row(const std::string& path) {
  io::RunHeader h;
  h.kind = "run";
  h.box = {0.006, 0.004};
  h.parameters = {{"mu_grain", 0.5}, {"mu_wall", 0.5}, {"critical_eps", 1e-3}};
  Frame fr;
  for (int g = 0; g < 3; ++g) fr.grains.add_disk(0.001, 2500, Vec2(0.001 + 0.002 * g, 0.001));
  fr.step = 40;
  fr.time = 0.004;
  fr.tilt_angle = 0.1;
  const Vec2 x{1, 0}, y{0, 1};
  fr.contacts.push_back(1, 0, Vec2(0.002, 0.001), x, 2.0, 1.0, 0, ContactStatus::slide);
  fr.contacts.push_back(2, 1, Vec2(0.004, 0.001), x, 1.0, 0.1, 0, ContactStatus::stick);
  fr.contacts.push_back(2, wall_floor, Vec2(0.005, 0.0), y, 3.0, 0.0, 0, ContactStatus::stick);
  h5::File f = h5::create(path, "run.h5");
  io::RunWriter w(f, h, fr.grains);
  w.append_frame(fr);
  f.close();
}

}  // namespace

TEST(Views, TheNetworkJoinsTheCentresOfEachPairWithItsForceOverTheMean) {
  const ScratchDir s("views");
  three_in_a_row((s.dir / "run.h5").string());
  const h5::File run = h5::open_read((s.dir / "run.h5").string(), "run.h5");
  const io::RunReader r(run);
  std::ostringstream grains, network;
  io::xdmf::Summary sum;
  {
    h5::File side = h5::create((s.dir / "run.xdmf.hdf5").string(), "run.xdmf.hdf5");
    sum = io::xdmf::write_run(grains, network, side, r, "run.h5", "run.xdmf.hdf5");
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
  EXPECT_EQ(io::lammps::write_contacts_dump(os, r, {}, {0.5, 0.5}, analysis::CriticalRule{}), 1u);
  const std::string text = os.str();
  EXPECT_EQ(text.substr(0, text.find("ITEM: BOX")),
            "ITEM: TIMESTEP\n40\nITEM: NUMBER OF ENTRIES\n2\n");
  EXPECT_EQ(text.substr(text.find("ITEM: ENTRIES")),
            "ITEM: ENTRIES id1 id2 fn ft critical\n2 1 2 1 1\n3 2 1 0.1 0\n");
}
