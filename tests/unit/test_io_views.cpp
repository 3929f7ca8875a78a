// io's views write what they are handed: to-lammps --contacts' critical column is the flag
// the caller's rule gives (the rule itself is decided outside io: test_reading_views.cpp).
#include "cdpile/io/h5.hpp"
#include "cdpile/io/lammps.hpp"
#include "cdpile/io/schema.hpp"
#include "scratch_dir.hpp"
#include "three_in_a_row.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

using namespace cdpile;
namespace h5 = cdpile::io::h5;

TEST(Views, TheContactsDumpWritesTheFlagsItIsGiven) {
  const ScratchDir s("views");
  test::three_in_a_row((s.dir / "run.h5").string());
  const h5::File run = h5::open_read((s.dir / "run.h5").string(), "run.h5");
  const io::RunReader r(run);
  std::ostringstream os;
  // a flag of the caller's: the contacts whose f_n is below 1.5 N/m
  EXPECT_EQ(io::lammps::write_contacts_dump(os, r, {}, [](double fn, double) { return fn < 1.5; }),
            1u);
  const std::string text = os.str();
  EXPECT_EQ(text.substr(text.find("ITEM: ENTRIES")),
            "ITEM: ENTRIES id1 id2 fn ft critical\n2 1 2 1 0\n3 2 1 0.1 1\n");
}
