// LAMMPS and LIGGGHTS dumps and scripts (io/lammps.hpp): parsing, the meaning of columns,
// and the conversion's geometry on cases computed by hand.
#include "cdpile/io/lammps.hpp"

#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace cdpile;
namespace lmp = cdpile::io::lammps;

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(LammpsDump, SnapshotsItemsAndCells) {
  const char* text =
      "ITEM: TIMESTEP\n10\nITEM: TIME\n0.5\nITEM: UNITS\nsi\nITEM: NUMBER OF ATOMS\n2\n"
      "ITEM: BOX BOUNDS xy xz yz pp ff pp\n0 1 0\n0 2 0\n-1 1 0\nITEM: ATOMS id x element\n1 0.25 "
      "Fe\n2 0.75 Ni\n"
      "ITEM: SOMETHING NEW\nwhatever\n"
      "ITEM: TIMESTEP\n20\nITEM: NUMBER OF ENTRIES\n0\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 "
      "1\nITEM: ENTRIES c_a[1]\n";
  const auto s = lmp::parse_dump(text, "d.txt");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].step, 10);
  EXPECT_EQ(*s[0].time, 0.5);
  EXPECT_EQ(s[0].units, "si");
  EXPECT_EQ(s[0].boundary[1], "ff");  // after the tilt factors' names
  EXPECT_EQ(s[0].box[3], 2.0);
  EXPECT_EQ(s[0].kind, lmp::Snapshot::Kind::atoms);
  EXPECT_EQ(s[0].values[1][1], 0.75);
  EXPECT_TRUE(std::isnan(s[0].values[2][0]));  // a text cell: not a number, ignored unless needed
  EXPECT_EQ(s[0].line[1], 15u);
  EXPECT_EQ(s[1].kind, lmp::Snapshot::Kind::entries);
  EXPECT_EQ(s[1].rows(), 0u);
  EXPECT_EQ(message_of([] { lmp::parse_dump("", "e.txt"); }), "e.txt: empty: not a LAMMPS dump");
  EXPECT_EQ(message_of([] { lmp::parse_dump("ITEM: NUMBER OF ATOMS\n1\n", "e.txt"); }),
            "e.txt: line 1: 'NUMBER OF ATOMS' before any ITEM: TIMESTEP (not a LAMMPS dump?)");
  EXPECT_EQ(message_of([] {
              lmp::parse_dump(
                  "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x\n1 2 3\n",
                  "e.txt");
            }),
            "e.txt: line 6: 3 fields, the header has 2");
}

TEST(LammpsScript, ComputesWallsIncludesAndConditionals) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("cdpile-lammps-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "in.dump")
      << "compute pl all pair/local dist force & # a comment\n   fx fy p1 p2 p4\n";
  std::ofstream(dir / "in.main")
      << "units si\ntimestep 1e-5\npair_style gran/hooke/history 1 NULL 1 NULL 0.5 1\n"
      << "fix floor all wall/gran hooke/history 1 NULL 1 NULL 0.5 1 yplane 0 NULL contacts\n"
      << "fix sides all wall/gran hooke/history 1 NULL 1 NULL 0.5 1 xplane 0 ${W}\n"
      << "if \"${cdump} > 0\" then \"variable x equal 1\" \"include in.dump\"\n";
  lmp::Script s;
  lmp::read_script((dir / "in.main").string(), s);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(s.units, "si");
  EXPECT_EQ(*s.timestep, 1e-5);
  EXPECT_EQ(s.pair_style, "gran/hooke/history");
  ASSERT_EQ(s.walls.size(), 2u);
  EXPECT_EQ(s.walls["floor"].axis, 'y');
  EXPECT_TRUE(s.walls["floor"].contacts);
  EXPECT_FALSE(s.walls["sides"].contacts);  // no per-atom output without `contacts`
  ASSERT_EQ(s.computes.count("pl"), 1u);
  EXPECT_EQ(s.computes["pl"].args,
            (std::vector<std::string>{"dist", "force", "fx", "fy", "p1", "p2", "p4"}));
  const auto roles =
      lmp::entry_column_roles({"c_pl[7]", "c_pl[2]", "c_pl[5]", "c_pl[6]", "other"}, s, {}, "d");
  EXPECT_EQ(roles, (std::vector<std::string>{"ftmag", "fn", "ftx", "fty", ""}));
  EXPECT_EQ(lmp::length_unit_of("si"), "m");
  EXPECT_EQ(lmp::length_unit_of("lj"), "");
}

TEST(LammpsScript, LiggghtsColumnsInTheirFixedOrder) {
  lmp::Script s;
  lmp::parse_script("compute a all pair/gran/local\ncompute w all wall/gran/local force id pos\n",
                    "in", ".", s);
  // defaults: pos (6) vel (6) id (3) force (3) torque (3) history (here 3) contactArea (1)
  std::vector<std::string> cols;
  for (int k = 1; k <= 25; ++k) cols.push_back("c_a[" + std::to_string(k) + "]");
  const auto r = lmp::entry_column_roles(cols, s, {}, "d");
  EXPECT_EQ(r[0], "x1");
  EXPECT_EQ(r[4], "y2");
  EXPECT_EQ(r[12], "id1");
  EXPECT_EQ(r[13], "id2");
  EXPECT_EQ(r[15], "fx");
  EXPECT_EQ(r[16], "fy");
  EXPECT_EQ(r[24], "");
  // a wall compute: the contact point and the particle, its id third
  std::vector<std::string> wc;
  for (int k = 1; k <= 12; ++k) wc.push_back("c_w[" + std::to_string(k) + "]");
  const auto rw = lmp::entry_column_roles(wc, s, {}, "d");
  EXPECT_EQ((std::vector<std::string>{rw[0], rw[1], rw[3], rw[6], rw[8], rw[9]}),
            (std::vector<std::string>{"px", "py", "x1", "wall", "id1", "fx"}));
  // explicit names win; two columns with one role are refused
  EXPECT_EQ(lmp::entry_column_roles({"a", "b"}, s, {{"a", "fn"}}, "d"),
            (std::vector<std::string>{"fn", ""}));
  EXPECT_EQ(message_of([&] {
              lmp::entry_column_roles({"fn", "b"}, s, {{"b", "fn"}}, "d");
            }),
            "d: columns fn and b both hold fn");
}

TEST(LammpsConvert, PairAcrossAPeriodicBoundaryUsesTheNearestImage) {
  // Two disks of radius 1 across x = 0 of a periodic box [0, 10): centres at 9.5 and 0.5,
  // 1 apart through the boundary (overlap 1); the contact point is midway, at x = 0 (or 10).
  const std::string atoms =
      "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp ff pp\n0 10\n0 10\n-1 1\n"
      "ITEM: ATOMS id x y radius\n1 9.5 5 1\n2 0.5 5 1\n";
  const std::string pairs =
      "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n1\nITEM: BOX BOUNDS pp ff pp\n0 10\n0 10\n-1 1\n"
      "ITEM: ENTRIES id1 id2 fx fy\n1 2 -3 0.5\n";
  const auto c = lmp::convert({{"a", atoms}, {"p", pairs}}, {});
  ASSERT_EQ(c.rows.size(), 1u);
  const auto& r = c.rows[0];
  EXPECT_NEAR(std::fmod(r.x + 10.0, 10.0), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(r.y, 5.0);
  // n from 2 to 1 is -x (1 sits left of 2 through the boundary): fn = F.n = 3, t = (0, -1)
  EXPECT_DOUBLE_EQ(r.fn, 3.0);
  EXPECT_DOUBLE_EQ(r.ft, -0.5);
  EXPECT_FALSE(c.has_theta);
}
