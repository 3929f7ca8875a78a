// Analysis products written as TSV and HDF5 read back to the same tables, missing values
// included (NA in TSV, a _defined flag in HDF5, never NaN in a file).
#include "cdpile/error.hpp"
#include "cdpile/io/products.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

using namespace cdpile;
using namespace cdpile::io;
using analysis::ColumnKind;
using analysis::Product;

namespace {
Product sample() {
  Product p;
  p.kind = "correlate";
  p.parameters = {{"window_deg", 1.0}, {"count", std::int64_t{3}}, {"mode", std::string("a b")}};
  p.results = {{"nu_c", 0.0812}};
  p.notes = {"a note"};
  auto& t = p.add_table("windows", "rows are windows");
  auto& th = t.add_column("theta", "deg");
  auto& n = t.add_column("n", "", ColumnKind::integer);
  auto& v = t.add_column("nu_bar", "");
  auto& s = t.add_column("se_over", "", ColumnKind::text);
  th.add(0.1);
  th.add(1.0 / 3.0);
  th.add(-2.5e-300);
  n.add_int(4);
  n.add_int(0);
  n.add(std::optional<double>());
  v.add(0.5);
  v.add(std::optional<double>());
  v.add(1e22);
  s.add_text("runs");
  s.add_text("none");
  s.add_text("frames");
  p.add_table("empty", "no rows").add_column("x", "m");
  return p;
}

void expect_same(const Product& a, const Product& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.tables.size(), b.tables.size());
  EXPECT_DOUBLE_EQ(*b.result("nu_c"), 0.0812);
  EXPECT_DOUBLE_EQ(*b.parameter("window_deg"), 1.0);
  EXPECT_DOUBLE_EQ(*b.parameter("count"), 3.0);
  EXPECT_EQ(std::get<std::string>(b.parameters.at("mode")), "a b");
  EXPECT_EQ(b.notes, a.notes);
  const auto& t = b.table("windows");
  ASSERT_EQ(t.rows(), 3u);
  EXPECT_EQ(t.column("theta").unit, "deg");
  for (std::size_t r = 0; r < 3; ++r) {
    for (const char* c : {"theta", "n", "nu_bar"}) {
      const auto x = a.table("windows").column(c).get(r), y = t.column(c).get(r);
      ASSERT_EQ(x.has_value(), y.has_value()) << c << r;
      if (x) {
        EXPECT_EQ(*x, *y) << c << r;  // exact: shortest round-trip text
      }
    }
    EXPECT_EQ(t.column("se_over").text[r], a.table("windows").column("se_over").text[r]);
  }
  EXPECT_EQ(b.table("empty").rows(), 0u);
}
}  // namespace

TEST(Products, TsvRoundTrip) {
  Product p = sample();
  std::ostringstream os;
  write_tsv(os, p, {provenance_now("correlate", "correlate in.h5", "in.h5")});
  const std::string text = os.str();
  for (const char* bad : {"\tnan", "nan\t", "\tinf", "inf\t", "\t-nan"})
    EXPECT_EQ(text.find(bad), std::string::npos) << text;
  EXPECT_NE(text.find("# columns: theta [deg] n [-] nu_bar [-] se_over [text]"), std::string::npos);
  EXPECT_NE(text.find("\t0\tNA\tnone\n"), std::string::npos) << text;
  ProductFile back = read_product_tsv(text, "x.tsv");
  expect_same(p, back.product);
  ASSERT_EQ(back.provenance.size(), 1u);
  EXPECT_EQ(back.provenance[0].command_line, "correlate in.h5");
}

TEST(Products, TsvRoundTripOfAMergedHistory) {
  // entries from several inputs carry the input they came through as a sixth field
  std::vector<Provenance> history = merge_histories(
      {{"run1.h5",
        {{"tilt-cd", "0.1.0", "tilt-cd p.h5 -o run1.h5", "p.h5", "2026-01-01T00:00:00Z"}}},
       {"run2.h5",
        {{"tilt-cd", "0.1.0", "tilt-cd q.h5 -o run2.h5", "q.h5", "2026-01-02T00:00:00Z"}}}});
  history.push_back(provenance_now("critical", "critical run1.h5 run2.h5", "run1.h5 run2.h5"));
  std::ostringstream os;
  write_tsv(os, sample(), history);
  EXPECT_NE(os.str().find("\ttilt-cd q.h5 -o run2.h5\trun2.h5\n"), std::string::npos) << os.str();
  const ProductFile back = read_product_tsv(os.str(), "x.tsv");
  ASSERT_EQ(back.provenance.size(), 3u);
  EXPECT_EQ(back.provenance[0].via, "run1.h5");
  EXPECT_EQ(back.provenance[1].via, "run2.h5");
  EXPECT_EQ(back.provenance[1].command_line, "tilt-cd q.h5 -o run2.h5");
  EXPECT_EQ(back.provenance[2].via, "");
  EXPECT_EQ(back.provenance[2].tool, "critical");
}

TEST(Products, HdfRoundTrip) {
  Product p = sample();
  h5::File f = h5::create_in_memory("mem.h5");
  write_hdf5(f, p, {provenance_now("correlate", "correlate in.h5", "in.h5")});
  ProductFile back = read_product_hdf5(f);
  expect_same(p, back.product);
  EXPECT_TRUE(h5::exists(f, "/tables/windows/nu_bar_defined"));
  auto raw = h5::read<double>(f, "/tables/windows/nu_bar", {3});
  for (double x : raw) EXPECT_TRUE(std::isfinite(x));
}

TEST(Products, ShortestRoundTripNumbers) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-0.0), "0");
  EXPECT_EQ(format_number(1e22), "1e+22");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "NA");
  EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "NA");
}

TEST(Products, TablesForPeoplePrintSixSignificantDigits) {
  // a tilt angle summed in steps of 0.01 deg, and a mean diameter (issue 34's examples)
  EXPECT_EQ(format_number(0.01 * 1312 + 1.8e-15, 6), "13.12");
  EXPECT_EQ(format_number(0.0010019143322225507, 6), "0.00100191");
  EXPECT_EQ(format_number(0.0010019143322225507), "0.0010019143322225507");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN(), 6), "NA");
  Product p = sample();
  p.results = {{"nu_c", 1.0 / 3.0}, {"runs", std::int64_t{123456789}}};
  std::ostringstream six, full;
  write_tsv(six, p, {}, {}, true, 6);
  write_tsv(full, p, {}, {}, true);
  EXPECT_NE(six.str().find("# result nu_c = 0.333333\n"), std::string::npos);
  EXPECT_NE(six.str().find("# result runs = 123456789\n"), std::string::npos);  // integers whole
  EXPECT_NE(six.str().find("\n0.333333\t0\tNA\t"), std::string::npos);  // theta 1/3, n 0
  EXPECT_NE(full.str().find("# result nu_c = 0.3333333333333333\n"), std::string::npos);
  // the parameters are the inputs as given, whatever the digits
  EXPECT_NE(six.str().find("# parameter window_deg = 1\n"), std::string::npos);
}

TEST(Products, TablesWithoutTheFileHeader) {
  Product p = sample();
  std::ostringstream with, without;
  write_tsv(with, p, {}, {"windows"});
  write_tsv(without, p, {}, {"windows"}, false);
  EXPECT_EQ(without.str().rfind("# table: windows\n", 0), 0u);  // the block first, no blank lines
  EXPECT_EQ(without.str().find("# kind:"), std::string::npos);
  EXPECT_EQ(without.str().find("# tables:"), std::string::npos);
  // the block itself is the same
  EXPECT_EQ(with.str().substr(with.str().find("# table: windows")), without.str());
}

TEST(Products, OneTableAndMissingTable) {
  Product p = sample();
  std::ostringstream os;
  write_tsv(os, p, {}, {"windows"});
  EXPECT_EQ(os.str().find("# table: empty"), std::string::npos);
  std::ostringstream os2;
  EXPECT_THROW(write_tsv(os2, p, {}, {"nope"}), Error);
  EXPECT_THROW(sample().table("nope"), Error);
}

namespace {
/// A product whose tables have no rows (correlate --from beyond the data): a text column
/// with no labels, and no notes at all.
Product empty_product() {
  Product p;
  p.kind = "correlate";
  p.results = {{"windows", std::int64_t{0}}};
  auto& t = p.add_table("windows", "no window");
  t.add_column("theta", "deg");
  t.add_column("n", "", ColumnKind::integer);
  t.add_column("se_over", "", ColumnKind::text);
  return p;
}

void expect_empty(const Product& b) {
  EXPECT_EQ(b.kind, "correlate");
  EXPECT_TRUE(b.notes.empty());
  const auto& t = b.table("windows");
  EXPECT_EQ(t.rows(), 0u);
  ASSERT_EQ(t.columns.size(), 3u);
  EXPECT_EQ(t.column("se_over").kind, ColumnKind::text);
  EXPECT_EQ(t.column("theta").unit, "deg");
}
}  // namespace

TEST(Products, EmptyTableHdfRoundTrip) {
  const Product p = empty_product();
  h5::File f = h5::create_in_memory("mem.h5");
  write_hdf5(f, p, {provenance_now("correlate", "correlate in.h5 --from 100", "in.h5")});
  const Product back = read_product_hdf5(f).product;
  expect_empty(back);
  EXPECT_EQ(back.table("windows").column("n").kind, ColumnKind::integer);  // TSV does not keep it
  EXPECT_TRUE(h5::attr_strings(f, "/tables/windows/se_over", "labels").empty());
  // and as the bytes a pipe carries (-o - into the next tool's -)
  const std::vector<char> image = h5::image_of(f);
  h5::File g = h5::open_image(image, "stdin");
  expect_empty(read_product_hdf5(g).product);
}

TEST(Products, EmptyTableTsvRoundTrip) {
  std::ostringstream os;
  write_tsv(os, empty_product(), {});
  expect_empty(read_product_tsv(os.str(), "x.tsv").product);
}

// docs/schema.md, "Ranges": an integer column holds ids and counts, read back as doubles and
// cast to integers: within 2^53; a count of rows in the TSV header is a size.
TEST(Products, ValuesOutsideTheirRangeAreRefused) {
  Product p = sample();
  h5::File f = h5::create_in_memory("mem.h5");
  write_hdf5(f, p, {provenance_now("correlate", "correlate in.h5", "in.h5")});
  const std::int64_t huge[3] = {4, -(std::int64_t{1} << 60), 0};
  H5Ldelete(f.id(), "/tables/windows/n", H5P_DEFAULT);
  h5::write(f, "/tables/windows/n", huge, {3});
  try {
    read_product_hdf5(f);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "mem.h5: /tables/windows/n: row 1: -1152921504606846976 is outside [-2^53, 2^53]");
  }
  std::ostringstream os;
  write_tsv(os, p, {}, {});
  std::string text = os.str();
  const auto at = text.find("windows=3");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 9, "windows=1e300");
  try {
    read_product_tsv(text, "p.tsv");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "p.tsv: bad '# tables:' entry 'windows=1e300'");
  }
}
