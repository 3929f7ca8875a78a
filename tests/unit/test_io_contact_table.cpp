// The plain-text table parser and the contact table reader (docs/contact-table.md).
#include "cdpile/error.hpp"
#include "cdpile/io/contact_table.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cdpile;
using namespace cdpile::io;

namespace {
std::string message_of(const std::string& text) {
  try {
    read_contact_table(text, "c.tsv");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(TextTable, TabCommaAndSpaceSeparated) {
  for (const char* text :
       {"# a comment\nx\ty\n1\t2\n3\t4.5e-1\n", "x,y\n1,2\n3, 0.45\n", "x   y\n  1 2\n3 0.45\n"}) {
    auto t = parse_text_tables(text, "t");
    ASSERT_EQ(t.size(), 1u) << text;
    ASSERT_EQ(t[0].columns, (std::vector<std::string>{"x", "y"}));
    ASSERT_EQ(t[0].rows(), 2u);
    EXPECT_DOUBLE_EQ(t[0].values[1][1], 0.45);
  }
}

TEST(TextTable, SeveralNamedTablesAndMissingValues) {
  const char* text =
      "# tool: critical\n# table: frames\n# columns: a [-] b [deg]\na\tb\n1\tNA\n\n\n"
      "# table: events\nc\tkind\n+2\truns\r\n";
  TextTableOptions o;
  o.allow_missing = true;
  o.text_columns = {"kind"};
  auto t = parse_text_tables(text, "t", o);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].name, "frames");
  EXPECT_TRUE(std::isnan(t[0].values[1][0]));
  EXPECT_EQ(t[1].name, "events");
  EXPECT_DOUBLE_EQ(t[1].values[0][0], 2.0);
  EXPECT_EQ(t[1].text[1][0], "runs");
  EXPECT_EQ(t[1].line[0], 10u);
}

TEST(TextTable, BadCellsNameTheLineAndColumn) {
  auto msg = [](const char* text) {
    try {
      parse_text_tables(text, "t.tsv");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(msg("x\ty\n1\tnan\n"), "t.tsv: line 2, column y: 'nan' is not a finite number");
  EXPECT_EQ(msg("x\ty\n1\tinf\n"), "t.tsv: line 2, column y: 'inf' is not a finite number");
  EXPECT_EQ(msg("x\ty\n1\t2\n1\n"), "t.tsv: line 3: 1 fields, the header has 2");
  EXPECT_EQ(msg("x\ty\n1\tNA\n"),
            "t.tsv: line 2, column y: missing value (NA) where a number is required");
  EXPECT_EQ(msg("x\tx\n"), "t.tsv: line 1: column 'x' appears twice");
  EXPECT_EQ(msg("x\ty\n1\t2e\n"), "t.tsv: line 2, column y: '2e' is not a finite number");
}

TEST(ContactTable, MinimalTableIsOneFrame) {
  auto c = read_contact_table("x\ty\tfn\tft\n0\t0\t1\t0.5\n1\t0\t2\t-0.2\n", "c.tsv");
  ASSERT_EQ(c.frames.size(), 1u);
  const Contacts& k = c.frames[0].contacts;
  ASSERT_EQ(k.size(), 2u);
  EXPECT_DOUBLE_EQ(k.point[1].x(), 1.0);
  EXPECT_DOUBLE_EQ(k.ft[1], -0.2);
  EXPECT_EQ(k.j[0], 0);  // no wall information: grain-grain
  EXPECT_FALSE(c.has_ids);
  EXPECT_FALSE(c.frames[0].theta);
}

TEST(ContactTable, FramesIdsWallsThetaStatus) {
  const char* text =
      "frame,theta,i,j,x,y,fn,ft,wall,status,extra\n"
      "20,1.5,1,2,0,0,1,0.5,0,2,9\n"
      "10,0.5,3,4,0,0,1,0.1,1,1,9\n"
      "20,1.5,5,6,1,1,1,0.1,0,1,9\n";
  auto c = read_contact_table(text, "c.csv");
  ASSERT_EQ(c.frames.size(), 2u);
  EXPECT_EQ(c.frames[0].frame, 10);
  EXPECT_DOUBLE_EQ(*c.frames[0].theta, 0.5);
  EXPECT_EQ(c.frames[0].contacts.j[0], wall_floor);  // wall = 1
  EXPECT_EQ(c.frames[1].contacts.size(), 2u);
  EXPECT_EQ(c.frames[1].contacts.status[0], ContactStatus::slide);
  EXPECT_EQ(c.frames[1].contacts.i[1], 5);
  EXPECT_TRUE(c.has_ids && c.has_walls && c.has_theta && c.has_status);
}

TEST(ContactTable, BadInputGivesOneLineErrors) {
  EXPECT_EQ(message_of("x\ty\tfn\n1\t2\t3\n"),
            "c.tsv: line 1: missing column 'ft' (the header has: x y fn)");
  EXPECT_EQ(message_of("x\ty\tfn\tft\n1\t2\t3\tNaN\n"),
            "c.tsv: line 2, column ft: 'NaN' is not a finite number");
  EXPECT_EQ(
      message_of("frame\ttheta\tx\ty\tfn\tft\n1\t2\t0\t0\t1\t0\n1\t3\t0\t0\t1\t0\n"),
      "c.tsv: line 3, column theta: theta differs from the value on line 2 of the same frame");
  EXPECT_EQ(message_of("frame\tx\ty\tfn\tft\n1.5\t0\t0\t1\t0\n"),
            "c.tsv: line 2, column frame: frame must be an integer");
  EXPECT_EQ(message_of("x\ty\tfn\tft\tstatus\n0\t0\t1\t0\t7\n"),
            "c.tsv: line 2, column status: status must be 0, 1 or 2");
  EXPECT_EQ(message_of(""), "c.tsv: no table (expected a header line: x y fn ft ...)");
  EXPECT_EQ(message_of("# only a comment\n"),
            "c.tsv: no table (expected a header line: x y fn ft ...)");
  // a header and no rows: no frames, not an error
  EXPECT_TRUE(read_contact_table("x\ty\tfn\tft\n", "c.tsv").frames.empty());
}

TEST(ContactTable, UnknownColumnsAreIgnoredWhateverTheyHold) {
  // docs/analysis.md promises it: a text column, a column of NA, an empty-looking label
  auto c = read_contact_table(
      "x\ty\tfn\tft\ttype\tnote\n0\t0\t1\t0.5\tglass\tNA\n1\t0\t2\t0.1\tsteel\t-\n", "c.tsv");
  ASSERT_EQ(c.frames.size(), 1u);
  EXPECT_EQ(c.frames[0].contacts.size(), 2u);
  EXPECT_DOUBLE_EQ(c.frames[0].contacts.fn[1], 2.0);
  // a known column still has to hold numbers
  EXPECT_EQ(message_of("x\ty\tfn\tft\ttype\n0\t0\tone\t0\tglass\n"),
            "c.tsv: line 2, column fn: 'one' is not a finite number");
}

TEST(ContactTable, APairGivenTwiceIsAnErrorNamingBothLines) {
  const char* text =
      "frame\ti\tj\tx\ty\tfn\tft\n"
      "1\t3\t4\t0\t0\t1\t0.5\n"
      "1\t5\t6\t1\t0\t1\t0.1\n"
      "2\t3\t4\t0\t0\t1\t0.5\n"    // another frame: not a repeat
      "1\t4\t3\t0\t0\t1\t-0.5\n";  // the same pair, listed from the other side
  EXPECT_EQ(
      message_of(text),
      "c.tsv: line 5: contact 4-3 of frame 1 is also on line 2 (give each contact once, or merge "
      "repeated rows: --duplicates merge)");
  // merged: counted once, the first row kept
  auto c = read_contact_table(text, "c.tsv", {Duplicates::merge});
  EXPECT_EQ(c.merged, 1u);
  ASSERT_EQ(c.frames.size(), 2u);
  EXPECT_EQ(c.frames[0].contacts.size(), 2u);
  EXPECT_EQ(c.frames[0].contacts.ft[0], 0.5);
  // a wall contact of grain 3 and its pair with grain 3 are different contacts
  auto w = read_contact_table("i\tj\tx\ty\tfn\tft\n3\t-1\t0\t0\t1\t0\n3\t1\t0\t1\t1\t0\n", "c.tsv");
  EXPECT_EQ(w.frames[0].contacts.size(), 2u);
}

TEST(ContactTable, RepeatsMustAgreeToBeMerged) {
  const char* text = "i\tj\tx\ty\tfn\tft\n3\t4\t0\t0\t1\t0.5\n3\t4\t0\t0\t2\t0.5\n";
  try {
    read_contact_table(text, "c.tsv", {Duplicates::merge});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "c.tsv: line 3: contact 3-4 is also on line 2 with another point or other forces: "
                 "not a repeat, cannot merge");
  }
}

TEST(ContactTable, WithoutIdsARepeatIsTheSamePoint) {
  const char* text = "x\ty\tfn\tft\n0.5\t0.25\t1\t0\n1\t0\t1\t0\n0.5\t0.25\t1\t0\n";
  EXPECT_EQ(message_of(text),
            "c.tsv: line 4: contact point (0.5, 0.25) is also on line 2 (give each contact once, "
            "or merge "
            "repeated rows: --duplicates merge)");
  EXPECT_EQ(read_contact_table(text, "c.tsv", {Duplicates::merge}).frames[0].contacts.size(), 2u);
}

TEST(ContactTable, LengthUnitComment) {
  EXPECT_EQ(
      read_contact_table("# length_unit: mm\nx\ty\tfn\tft\n0\t0\t1\t0\n", "c.tsv").length_unit,
      "mm");
  EXPECT_EQ(read_contact_table("x\ty\tfn\tft\n0\t0\t1\t0\n", "c.tsv").length_unit, "");
}

// docs/schema.md, "Ranges": with the grains' diameter known (localnu's --diameter), a point
// more than 1e9 D from the origin is no pile's contact.
TEST(ContactTable, APointBeyondItsRangeIsRefused) {
  const std::string text = "x\ty\tfn\tft\n0\t0\t1\t0\n1e300\t0\t1\t0\n";
  EXPECT_NO_THROW(read_contact_table(text, "c.tsv", {}));  // no diameter, no bound
  try {
    read_contact_table(text, "c.tsv", {}, 1e-3);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "c.tsv: line 3, column x: 1e+300 is outside [-1e9 D, 1e9 D] (D = 0.001)");
  }
}
