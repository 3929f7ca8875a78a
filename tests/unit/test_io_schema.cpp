// The common schema: exact round trips (file, and in-memory image as a pipe carries it),
// resume truncation, atomic output, and one clear error per kind of bad input.
#include "cdpile/io/files.hpp"
#include "cdpile/io/sample.hpp"
#include "cdpile/io/schema.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

using namespace cdpile;
namespace h5 = cdpile::io::h5;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("cdpile-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(std::random_device{}()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

/// A frame with every field filled by awkward values (negative, tiny, huge), so an exact
/// comparison would catch any lossy conversion.
Frame random_frame(std::size_t n, std::size_t k, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  Frame fr;
  fr.step = 123456789012LL;
  fr.time = 0.1 + u();
  fr.tilt_angle = 0.3 * u();
  for (std::size_t q = 0; q < n; ++q) {
    // Inside the box of write_run (0.12 x 0.05 m) enlarged by its width, as the reader asks.
    fr.grains.add_disk(1e-3 * (0.4 + u()), 2500, Vec2(0.3 * u() - 0.1, 1e-300 + 0.15 * u()),
                       q % 3 == 0 ? Species::floor : Species::free);
    fr.grains.velocity.back() = Vec2(-u(), 1e-12 * u());
    fr.grains.orientation.back() = 100 * u();
    fr.grains.angular_velocity.back() = -1e5 * u();
  }
  // Every pair at most once (the reader refuses a pair listed twice): grain pairs, with
  // every fourth contact on a wall.
  std::vector<std::pair<std::int32_t, std::int32_t>> grain_pairs, wall_pairs;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < a; ++b)
      grain_pairs.emplace_back(static_cast<std::int32_t>(a), static_cast<std::int32_t>(b));
    for (std::int32_t w : {wall_floor, wall_left, wall_right})
      wall_pairs.emplace_back(static_cast<std::int32_t>(a), w);
  }
  std::size_t next_grain = 0, next_wall = 0;
  for (std::size_t q = 0; q < k; ++q) {
    const bool wall =
        (q % 4 == 0 && next_wall < wall_pairs.size()) || next_grain == grain_pairs.size();
    const auto [i, j] = wall ? wall_pairs.at(next_wall++) : grain_pairs.at(next_grain++);
    fr.contacts.push_back(i, j, Vec2(u(), u()), Vec2(std::cos(q), std::sin(q)), 1e-9 + u(),
                          u() - 0.5, -1e-7 * u(), static_cast<ContactStatus>(q % 3));
  }
  return fr;
}

void expect_same(const Grains& a, const Grains& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t q = 0; q < a.size(); ++q) {
    EXPECT_EQ(a.radius[q], b.radius[q]);
    EXPECT_EQ(a.mass[q], b.mass[q]);
    EXPECT_EQ(a.inertia[q], b.inertia[q]);
    EXPECT_EQ(a.species[q], b.species[q]);
    EXPECT_EQ(a.position[q], b.position[q]);
    EXPECT_EQ(a.velocity[q], b.velocity[q]);
    EXPECT_EQ(a.orientation[q], b.orientation[q]);
    EXPECT_EQ(a.angular_velocity[q], b.angular_velocity[q]);
  }
}

void expect_same(const Contacts& a, const Contacts& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.i, b.i);
  EXPECT_EQ(a.j, b.j);
  EXPECT_EQ(a.point, b.point);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.fn, b.fn);
  EXPECT_EQ(a.ft, b.ft);
  EXPECT_EQ(a.gap, b.gap);
  EXPECT_EQ(a.status, b.status);
}

io::RunHeader test_header() {
  io::RunHeader h;
  h.kind = "run";
  h.box = {0.12, 0.05};
  h.parameters = {{"mu_grain", 0.5},
                  {"grains", std::int64_t{7}},
                  {"time_step_s", 1e-4},
                  {"integrator", std::string("moreau-jean")}};
  h.results = {{"avalanche_angle_deg", 19.5}};
  h.provenance = {
      {"deposit", "0.1.0", "deposit --grains 7 -o 'a b.h5'", "", "2026-11-22T00:00:00Z"}};
  return h;
}

/// Writes a run of `frames` frames with `n` grains and a series of `steps` steps.
std::vector<Frame> write_run(h5::File& f, std::size_t n, std::size_t frames, std::size_t steps) {
  std::vector<Frame> out;
  for (std::size_t q = 0; q < frames; ++q) {
    out.push_back(random_frame(n, 3 * n + q, 42 + q));
    out.back().step = static_cast<std::int64_t>(10 * q);
    out.back().grains.radius = out.front().grains.radius;
    out.back().grains.mass = out.front().grains.mass;
    out.back().grains.inertia = out.front().grains.inertia;
    out.back().grains.species = out.front().grains.species;
  }
  io::RunWriter w(f, test_header(), out.front().grains);
  for (const auto& fr : out) w.append_frame(fr);
  w.append_series(io::sample_series(steps));
  return out;
}

void expect_run(const io::RunReader& r, const std::vector<Frame>& frames, std::size_t steps) {
  ASSERT_EQ(r.frame_count(), frames.size());
  EXPECT_EQ(r.header().kind, "run");
  EXPECT_EQ(r.header().box.width, 0.12);
  EXPECT_EQ(std::get<double>(r.header().parameters.at("mu_grain")), 0.5);
  EXPECT_EQ(std::get<std::int64_t>(r.header().parameters.at("grains")), 7);
  EXPECT_EQ(std::get<std::string>(r.header().parameters.at("integrator")), "moreau-jean");
  EXPECT_EQ(std::get<double>(r.header().results.at("avalanche_angle_deg")), 19.5);
  ASSERT_EQ(r.header().provenance.size(), 1u);
  EXPECT_EQ(r.header().provenance[0].command_line, "deposit --grains 7 -o 'a b.h5'");
  for (std::size_t q = 0; q < frames.size(); ++q) {
    Frame got = r.frame(q);
    EXPECT_EQ(got.step, frames[q].step);
    EXPECT_EQ(got.time, frames[q].time);
    EXPECT_NEAR(got.tilt_angle, frames[q].tilt_angle, 1e-15);  // stored in degrees
    expect_same(got.grains, frames[q].grains);
    expect_same(got.contacts, frames[q].contacts);
  }
  io::Series s = r.series();
  io::Series want = io::sample_series(steps);
  EXPECT_EQ(s.step, want.step);
  EXPECT_EQ(s.time, want.time);
  EXPECT_EQ(s.real, want.real);
  EXPECT_EQ(s.integer, want.integer);
  EXPECT_EQ(s.unit.at("tilt_angle"), "degree");  // the H5MD units module symbol
}

}  // namespace

TEST(Schema, RoundTripThroughAFileIsExact) {
  TempDir dir;
  const std::string path = dir / "run.h5";
  std::vector<Frame> frames;
  {
    io::Output out(path, false);
    frames = write_run(out.create_hdf5(), 7, 3, 10);
    out.commit();
  }
  io::Input in(path);
  expect_run(io::RunReader(in.hdf5()), frames, 10);
}

TEST(Schema, RoundTripThroughAnInMemoryImageIsExact) {
  // What `tool -o - | tool -` does: the writer's file image, read back as bytes.
  std::vector<char> bytes;
  std::vector<Frame> frames;
  {
    h5::File f = h5::create_in_memory("stdout");
    frames = write_run(f, 7, 2, 5000);
    bytes = h5::image_of(f);
  }
  ASSERT_TRUE(io::has_hdf5_signature(bytes));
  h5::File g = h5::open_image(bytes, "stdin");
  expect_run(io::RunReader(g), frames, 5000);
}

TEST(Schema, ObservablesShareOneClockAsH5mdHardLinks) {
  h5::File f = h5::create_in_memory("mem");
  write_run(f, 3, 1, 4);
  // Every element of /observables has step and time; they are the same datasets.
  H5O_info_t a, b;
  H5Oget_info_by_name2(f.id(), "/observables/contacts/step", &a, H5O_INFO_BASIC, H5P_DEFAULT);
  H5Oget_info_by_name2(f.id(), "/observables/tilt_angle/step", &b, H5O_INFO_BASIC, H5P_DEFAULT);
  EXPECT_EQ(a.addr, b.addr);  // one object, two links
  EXPECT_GE(a.rc, 2u);
  EXPECT_EQ(h5::attr_ints(f, "/h5md", "version"), (std::vector<std::int64_t>{1, 1}));
  EXPECT_EQ(h5::attr_int(f, "/particles/grains/box", "dimension"), 2);
}

namespace {
/// Whether an attribute's type is a fixed-length or variable-length string, and its cset.
struct StringKind {
  bool is_string = false, variable = false;
  H5T_cset_t cset = H5T_CSET_ERROR;
  int rank = -1;
};
StringKind string_kind(const h5::File& f, const std::string& path, const std::string& name) {
  StringKind k;
  h5::Handle obj(H5Oopen(f.id(), path.c_str(), H5P_DEFAULT));
  h5::Handle a(H5Aopen(obj.id(), name.c_str(), H5P_DEFAULT));
  if (!a.valid()) return k;
  h5::Handle t(H5Aget_type(a.id()));
  h5::Handle sp(H5Aget_space(a.id()));
  k.is_string = H5Tget_class(t.id()) == H5T_STRING;
  k.variable = H5Tis_variable_str(t.id()) > 0;
  k.cset = H5Tget_cset(t.id());
  k.rank = H5Sget_simple_extent_ndims(sp.id());
  return k;
}
}  // namespace

TEST(Schema, H5mdMetadataFollowsTheSpecification) {
  // H5MD 1.1: author name, creator name and version are fixed-length scalar strings;
  // box/boundary a fixed-length string array of D; the units module is declared
  // (version [1, 0], system SI) and unit attributes are variable-length ASCII strings.
  io::set_author("Ada Lovelace <ada@example.org>");
  h5::File f = h5::create_in_memory("mem");
  write_run(f, 3, 1, 4);
  for (auto [path, name] :
       std::initializer_list<std::pair<const char*, const char*>>{{"/h5md/author", "name"},
                                                                  {"/h5md/author", "email"},
                                                                  {"/h5md/creator", "name"},
                                                                  {"/h5md/creator", "version"}}) {
    const StringKind k = string_kind(f, path, name);
    EXPECT_TRUE(k.is_string && !k.variable && k.rank == 0) << path << " " << name;
  }
  EXPECT_EQ(h5::attr_string(f, "/h5md/author", "name"), "Ada Lovelace");
  EXPECT_EQ(h5::attr_string(f, "/h5md/author", "email"), "ada@example.org");
  EXPECT_EQ(h5::attr_string(f, "/h5md/creator", "name"), "cdpile");
  const StringKind b = string_kind(f, "/particles/grains/box", "boundary");
  EXPECT_TRUE(b.is_string && !b.variable && b.rank == 1);
  EXPECT_EQ(h5::attr_strings(f, "/particles/grains/box", "boundary"),
            (std::vector<std::string>{"none", "none"}));
  EXPECT_EQ(h5::attr_ints(f, "/h5md/modules/units", "version"), (std::vector<std::int64_t>{1, 0}));
  EXPECT_EQ(h5::attr_string(f, "/h5md/modules/units", "system"), "SI");
  const StringKind u = string_kind(f, "/observables/tilt_angle/value", "unit");
  EXPECT_TRUE(u.is_string && u.variable && u.cset == H5T_CSET_ASCII && u.rank == 0);
  EXPECT_EQ(h5::attr_string(f, "/observables/tilt_angle/value", "unit"), "degree");
  EXPECT_EQ(h5::attr_string(f, "/contacts/tilt_angle", "unit"), "degree");
  EXPECT_FALSE(h5::has_attr(f, "/observables/contacts/value", "unit"));  // dimensionless: no unit
  io::set_author("");  // back to the default for the other tests
}

TEST(Schema, AuthorTextIsNameAndOptionalEmail) {
  EXPECT_EQ(io::parse_author("  Jean Dupont ").name, "Jean Dupont");
  EXPECT_EQ(io::parse_author("Jean Dupont").email, "");
  const io::Author a = io::parse_author("Jean Dupont <jd@lab.fr>");
  EXPECT_EQ(a.name, "Jean Dupont");
  EXPECT_EQ(a.email, "jd@lab.fr");
  io::set_author("Someone Else");
  EXPECT_EQ(io::author().name, "Someone Else");
  io::set_author("");
  EXPECT_FALSE(io::author().name.empty());  // the environment or the password database
}

/// A variable-length UTF-8 string attribute, as cdpile wrote every text attribute before
/// the fixed-length ones (a scalar unless `list`).
void set_variable_attr(const h5::File& f, const std::string& path, const std::string& name,
                       const std::vector<std::string>& v, bool list) {
  h5::Handle obj(H5Oopen(f.id(), path.c_str(), H5P_DEFAULT));
  if (H5Aexists(obj.id(), name.c_str()) > 0) H5Adelete(obj.id(), name.c_str());
  h5::Handle t(H5Tcopy(H5T_C_S1));
  H5Tset_size(t.id(), H5T_VARIABLE);
  H5Tset_cset(t.id(), H5T_CSET_UTF8);
  const hsize_t n = v.size();
  h5::Handle space(list ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_SCALAR));
  h5::Handle a(H5Acreate2(obj.id(), name.c_str(), t.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT));
  std::vector<const char*> p;
  for (const auto& x : v) p.push_back(x.c_str());
  ASSERT_GE(H5Awrite(a.id(), t.id(), p.data()), 0);
}

TEST(Schema, FilesWithVariableLengthMetadataStillRead) {
  // Files written before the H5MD fixes: variable-length UTF-8 author, creator and
  // boundary, unit 'deg', no units module. Every reader still takes them.
  TempDir dir;
  const std::string path = dir / "old.h5";
  std::vector<Frame> frames;
  {
    io::Output out(path, false);
    h5::File& f = out.create_hdf5();
    frames = write_run(f, 4, 2, 6);
    set_variable_attr(f, "/h5md/author", "name", {"cdpile user"}, false);
    set_variable_attr(f, "/h5md/creator", "name", {"cdpile"}, false);
    set_variable_attr(f, "/h5md/creator", "version", {"0.1.0"}, false);
    set_variable_attr(f, "/particles/grains/box", "boundary", {"none", "none"}, true);
    set_variable_attr(f, "/observables/tilt_angle/value", "unit", {"deg"}, false);
    set_variable_attr(f, "/contacts/tilt_angle", "unit", {"deg"}, false);
    H5Ldelete(f.id(), "/h5md/modules/units", H5P_DEFAULT);
    H5Ldelete(f.id(), "/h5md/modules", H5P_DEFAULT);
    out.commit();
  }
  io::Input in(path);
  ASSERT_TRUE(string_kind(in.hdf5(), "/h5md/author", "name").variable);
  io::RunReader r(in.hdf5());
  ASSERT_EQ(r.frame_count(), 2u);
  expect_same(r.frame(1).contacts, frames[1].contacts);
  EXPECT_EQ(r.series().unit.at("tilt_angle"), "deg");
  EXPECT_EQ(h5::attr_string(in.hdf5(), "/h5md/author", "name"), "cdpile user");
  EXPECT_EQ(h5::attr_strings(in.hdf5(), "/particles/grains/box", "boundary"),
            (std::vector<std::string>{"none", "none"}));
}

TEST(Schema, ReopenDropsWhatCameAfterTheCheckpoint) {
  h5::File f = h5::create_in_memory("mem");
  auto frames = write_run(f, 5, 3, 40);  // frames at steps 0, 10, 20; series steps 0..39
  io::RunWriter w = io::RunWriter::reopen(f, 15);
  EXPECT_EQ(w.frames(), 2u);
  io::RunReader r(f);
  ASSERT_EQ(r.frame_count(), 2u);
  expect_same(r.frame(1).contacts, frames[1].contacts);
  EXPECT_EQ(r.series().size(), 16u);
  // Appending goes on after the kept rows.
  w.append_frame(frames[2]);
  io::RunReader r2(f);
  ASSERT_EQ(r2.frame_count(), 3u);
  expect_same(r2.frame(2).contacts, frames[2].contacts);
}

TEST(Schema, MergedHistoriesKeepEveryInputsChain) {
  const io::Provenance dep1{"deposit", "0.1.0", "deposit -o p1.h5", "", "2026-01-01T00:00:00Z"};
  const io::Provenance tilt1{"tilt-cd", "0.1.0", "tilt-cd p1.h5 -o run1.h5", "p1.h5",
                             "2026-01-01T00:01:00Z"};
  const io::Provenance dep2{"deposit", "0.1.0", "deposit -o p2.h5", "", "2026-01-02T00:00:00Z"};
  // one input: a linear chain, unchanged
  auto one = io::merge_histories({{"run1.h5", {dep1, tilt1}}});
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[1].command_line, tilt1.command_line);
  EXPECT_EQ(one[0].via + one[1].via, "");
  // several: every chain in input order, each entry marked with its input
  auto two =
      io::merge_histories({{"run1.h5", {dep1, tilt1}}, {"table.tsv", {}}, {"run2.h5", {dep2}}});
  ASSERT_EQ(two.size(), 3u);
  EXPECT_EQ(two[0].command_line, dep1.command_line);
  EXPECT_EQ(two[0].via, "run1.h5");
  EXPECT_EQ(two[1].via, "run1.h5");
  EXPECT_EQ(two[2].command_line, dep2.command_line);
  EXPECT_EQ(two[2].via, "run2.h5");
  // merged again (a product of products): the path of inputs
  auto deep = io::merge_histories({{"c.h5", two}, {"d.h5", {dep1}}});
  EXPECT_EQ(deep[2].via, "c.h5 > run2.h5");
  EXPECT_EQ(deep[3].via, "d.h5");
  // written and read back: `via` only where it is set
  io::RunHeader h = test_header();
  h.provenance = two;
  h.provenance.push_back(io::provenance_now("critical", "critical run1.h5 table.tsv run2.h5",
                                            "run1.h5 table.tsv run2.h5"));
  h5::File f = h5::create_in_memory("merged.h5");
  io::write_header(f, h);
  EXPECT_FALSE(h5::has_attr(f, "/provenance/003", "via"));
  EXPECT_EQ(h5::attr_string(f, "/provenance/002", "via"), "run2.h5");
  const io::RunHeader back = io::read_header(f);
  ASSERT_EQ(back.provenance.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(back.provenance[k].command_line, h.provenance[k].command_line);
    EXPECT_EQ(back.provenance[k].via, h.provenance[k].via);
  }
}

TEST(Output, RefusesToOverwriteWithoutForceAndLeavesNoPartialFile) {
  TempDir dir;
  const std::string path = dir / "keep.h5";
  { std::ofstream(path) << "precious"; }
  try {
    io::Output out(path, false);
    FAIL() << "an existing file was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              path + ": exists; not overwritten (use --force to replace it)");
  }
  {
    io::Output out(path, true);  // forced, but the run fails before commit
    write_run(out.create_hdf5(), 3, 1, 2);
    EXPECT_TRUE(fs::exists(out.temporary_path()));
  }
  std::ifstream in(path);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "precious");  // the good file is untouched
  std::size_t files = 0;
  for ([[maybe_unused]] auto& e : fs::directory_iterator(dir.path)) ++files;
  EXPECT_EQ(files, 1u);  // no temporary left behind
}

// ---------------------------------------------------------------------------------------
// Bad input: each gives one Error naming the file, the path inside it and what is wrong.

namespace {

/// Writes a valid run to `path`, lets `damage` change it, and returns the reader's error.
template <class Damage>
std::string error_after(const std::string& path, Damage damage) {
  {
    io::Output out(path, true);
    write_run(out.create_hdf5(), 4, 2, 3);
    out.commit();
  }
  {
    h5::File f = h5::open_write(path, path);
    damage(f);
  }
  try {
    io::Input in(path);
    io::RunReader r(in.hdf5());
    for (std::size_t k = 0; k < r.frame_count(); ++k) r.frame(k);
    r.series();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

void replace(const h5::File& f, const std::string& path, const std::vector<double>& v,
             const std::vector<hsize_t>& dims) {
  H5Ldelete(f.id(), path.c_str(), H5P_DEFAULT);
  h5::write(f, path, v.data(), dims);
}

}  // namespace

TEST(ReaderErrors, MissingGroup) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(
      error_after(p, [](h5::File& f) { H5Ldelete(f.id(), "/particles/grains/box", H5P_DEFAULT); }),
      p + ": /particles/grains/box: missing group");
}

TEST(ReaderErrors, WrongSchemaVersion) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(
      error_after(p, [](h5::File& f) { h5::set_attr(f, "/", "schema_version", std::int64_t{2}); }),
      p + ": /: schema version 2, this build reads version 1");
}

TEST(ReaderErrors, NotACdpileFile) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p, [](h5::File& f) { H5Adelete(f.id(), "schema"); }),
            p + ": /: not a cdpile file (no schema = \"cdpile\" attribute)");
}

TEST(ReaderErrors, WrongShape) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          replace(f, "/particles/grains/mass", std::vector<double>(8, 1.0), {4, 2});
                        }),
            p + ": /particles/grains/mass: expected shape [4], found [4 x 2]");
  EXPECT_EQ(
      error_after(
          p, [](h5::File& f) { replace(f, "/contacts/fn", std::vector<double>(3, 1.0), {3}); }),
      p + ": /contacts/fn: expected 25 rows");
}

TEST(ReaderErrors, NotFiniteValues) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          replace(f, "/particles/grains/radius", {1e-3, NAN, 1e-3, 1e-3}, {4});
                        }),
            p + ": /particles/grains/radius: non-finite value (NaN) at element 1");
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          std::vector<double> pos(2 * 4 * 2, 0.0);
                          pos[5] = INFINITY;
                          H5Ldelete(f.id(), "/particles/grains/position/value", H5P_DEFAULT);
                          h5::write(f, "/particles/grains/position/value", pos.data(), {2, 4, 2});
                        }),
            p + ": /particles/grains/position/value: non-finite value (inf) at element 5");
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          std::vector<double> v(2 * 4 * 2, 0.0);
                          v[13] = NAN;
                          H5Ldelete(f.id(), "/particles/grains/velocity/value", H5P_DEFAULT);
                          h5::write(f, "/particles/grains/velocity/value", v.data(), {2, 4, 2});
                        }),
            p + ": /particles/grains/velocity/value: non-finite value (NaN) at element 13");
}

TEST(ReaderErrors, RunWithoutObservables) {
  // A run always records its per-step observables; without them the analyses would see a
  // run of zero steps (no theta_c, no events) and say nothing.
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p, [](h5::File& f) { H5Ldelete(f.id(), "/observables", H5P_DEFAULT); }),
            p + ": /observables: missing group (a run records its per-step observables)");
  // a pile may lack them
  const auto q = dir / "pile.h5";
  EXPECT_EQ(error_after(q,
                        [](h5::File& f) {
                          H5Ldelete(f.id(), "/observables", H5P_DEFAULT);
                          h5::set_attr(f, "/", "kind", std::string("pile"));
                        }),
            "no error");
}

TEST(ReaderErrors, NegativeRadius) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          replace(f, "/particles/grains/radius", {1e-3, 1e-3, -1e-3, 1e-3}, {4});
                        }),
            p + ": /particles/grains/radius: radius of grain 2 is not positive");
}

TEST(ReaderErrors, InconsistentContactTable) {
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          std::int64_t c[2] = {12, 99};
                          H5Ldelete(f.id(), "/contacts/count", H5P_DEFAULT);
                          h5::write(f, "/contacts/count", c, {2});
                        }),
            p + ": /contacts/i: holds 25 contacts, the frames count 111");
}

TEST(ReaderErrors, TruncatedFile) {
  TempDir dir;
  const auto p = dir / "a.h5";
  {
    io::Output out(p, false);
    write_run(out.create_hdf5(), 4, 2, 3);
    out.commit();
  }
  fs::resize_file(p, fs::file_size(p) / 2);
  std::string msg = "no error";
  try {
    io::Input in(p);
    io::RunReader r(in.hdf5());
    for (std::size_t k = 0; k < r.frame_count(); ++k) r.frame(k);
  } catch (const Error& e) {
    msg = e.what();
  }
  EXPECT_EQ(msg.rfind(p + ": ", 0), 0u) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
}

TEST(ReaderErrors, NotHdf5) {
  TempDir dir;
  const auto p = dir / "a.h5";
  { std::ofstream(p) << "x\ty\tfn\tft\n1\t2\t3\t4\n"; }
  io::Input in(p);
  EXPECT_FALSE(in.is_hdf5());
  try {
    in.hdf5();
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), p + ": not an HDF5 file (no HDF5 signature)");
  }
}

TEST(ReaderErrors, MissingFile) {
  try {
    io::Input in("/nonexistent/x.h5");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/x.h5: no such file");
  }
}

TEST(ReaderErrors, MagnitudesNoPileCanHave) {
  // The box of write_run is 0.12 x 0.05 m: L = 0.12 m, speeds up to 1000 sqrt(9.81 L).
  TempDir dir;
  const auto p = dir / "a.h5";
  EXPECT_EQ(error_after(p,
                        [](h5::File& f) {
                          replace(f, "/particles/grains/radius", {1e-3, 0.07, 1e-3, 1e-3}, {4});
                        }),
            p + ": /particles/grains/radius: radius of grain 1 is 0.07 m, more than half the box "
                "width 0.12 m");
  auto state = [](const std::string& element, std::size_t at, double value) {
    return [=](h5::File& f) {
      std::vector<hsize_t> dims;
      auto v = h5::read<double>(f, element, {}, &dims);
      v[at] = value;
      replace(f, element, v, dims);
    };
  };
  EXPECT_EQ(
      error_after(p, state("/particles/grains/position/value", 8 + 2 * 2, -0.25)),
      p + ": /particles/grains/position/value: frame 1: grain 2 at (-0.25, " +
          [&] {
            io::Input in(p);
            char b[32];
            std::snprintf(b, sizeof b, "%.6g",
                          h5::read<double>(in.hdf5(), "/particles/grains/position/value", {})[13]);
            return std::string(b);
          }() +
          ") m is outside the box [0, 0.12] x [0, 0.05] m enlarged by 0.12 m");
  const std::string fast = error_after(p, state("/particles/grains/velocity/value", 3, 2e3));
  EXPECT_EQ(fast.rfind(p + ": /particles/grains/velocity/value: frame 0: grain 1 moves at 20", 0),
            0u)
      << fast;
  EXPECT_NE(fast.find(" m/s (its rim included), more than 1000 sqrt(g L) = 1084.99 m/s"),
            std::string::npos)
      << fast;
}

TEST(ReaderErrors, PairListedTwiceInAFrame) {
  TempDir dir;
  const auto p = dir / "a.h5";
  std::int32_t i = 0, j = 0;
  // Row 2 of frame 0 becomes row 1's pair, the other way round: the same two grains.
  const std::string e = error_after(p, [&](h5::File& f) {
    auto vi = h5::read<std::int32_t>(f, "/contacts/i", {}),
         vj = h5::read<std::int32_t>(f, "/contacts/j", {});
    i = vi[1];
    j = vj[1];
    ASSERT_GE(j, 0);
    vi[2] = j;
    vj[2] = i;
    H5Ldelete(f.id(), "/contacts/i", H5P_DEFAULT);
    H5Ldelete(f.id(), "/contacts/j", H5P_DEFAULT);
    h5::write(f, "/contacts/i", vi);
    h5::write(f, "/contacts/j", vj);
  });
  EXPECT_EQ(e, p + ": /contacts/i: rows 1 and 2: the contact of " + std::to_string(i) + " and " +
                   std::to_string(j) + " is listed twice in frame 0");
}

TEST(ReaderErrors, ClaimsMoreThanTheFileHolds) {
  // An extendible dataset stretched to 4e8 rows without a byte written: the file stays
  // small, and the reader refuses before allocating 3.2 GB.
  TempDir dir;
  const auto p = dir / "a.h5";
  const std::string e = error_after(p, [](h5::File& f) {
    const hsize_t rows[1] = {400000000};
    h5::Handle d(H5Dopen2(f.id(), "/observables/tilt_angle/value", H5P_DEFAULT));
    ASSERT_GE(H5Dset_extent(d.id(), rows), 0);
  });
  EXPECT_NE(e.find(": /observables/tilt_angle/value: "), std::string::npos) << e;
  EXPECT_NE(e.find("expected shape"), std::string::npos) << e;  // checked against the clock first
  const std::string g = error_after(p, [](h5::File& f) {
    for (const char* c : {"/observables/tilt_angle/step", "/observables/tilt_angle/value"}) {
      h5::Handle d(H5Dopen2(f.id(), c, H5P_DEFAULT));
      const hsize_t rows[1] = {400000000};
      ASSERT_GE(H5Dset_extent(d.id(), rows), 0);
    }
  });
  // The step of the series' clock (the first observable, whose step the others link to).
  EXPECT_EQ(g.rfind(p + ": /observables/", 0), 0u) << g;
  EXPECT_NE(g.find("/step: too large (claims 400000000 elements, 3.2 GB, in a file of "),
            std::string::npos)
      << g;
}

TEST(Schema, FilesHaveChecksummedMetadataAndFixedLengthText) {
  TempDir dir;
  const auto p = dir / "a.h5";
  {
    io::Output out(p, false);
    write_run(out.create_hdf5(), 3, 1, 2);
    out.commit();
  }
  std::ifstream in(p, std::ios::binary);
  char head[9];
  in.read(head, 9);
  EXPECT_EQ(head[8], 3) << "superblock version (HDF5 1.10's format, with checksums)";
  io::Input f(p);
  for (const auto& [path, name] :
       std::vector<std::pair<std::string, std::string>>{{"/", "kind"},
                                                        {"/", "schema"},
                                                        {"/provenance/000", "tool"},
                                                        {"/provenance/000", "command_line"}})
    EXPECT_FALSE(string_kind(f.hdf5(), path, name).variable) << path << " " << name;
}

// The ranges of docs/schema.md, "Ranges": a value of the right type in the right place
// that no pile or run can hold is refused, naming the dataset, the element and the value.
TEST(ReaderErrors, ValuesOutsideTheirRange) {
  TempDir dir;
  const auto p = dir / "a.h5";
  auto set = [](const std::string& path, std::size_t at, double value) {
    return [=](h5::File& f) {
      std::vector<hsize_t> dims;
      auto v = h5::read<double>(f, path, {}, &dims);
      v[at] = value;
      replace(f, path, v, dims);
    };
  };
  auto set_int = [](const std::string& path, std::size_t at, std::int64_t value) {
    return [=](h5::File& f) {
      std::vector<hsize_t> dims;
      auto v = h5::read<std::int64_t>(f, path, {}, &dims);
      v[at] = value;
      H5Ldelete(f.id(), path.c_str(), H5P_DEFAULT);
      h5::write(f, path, v.data(), dims);
    };
  };
  EXPECT_EQ(error_after(p, set("/contacts/tilt_angle", 1, 1e300)),
            p + ": /contacts/tilt_angle: frame 1: 1e+300 deg is outside [-90, 90] deg");
  EXPECT_EQ(error_after(p, set("/contacts/tilt_angle", 0, 90.00000000000001)),
            p + ": /contacts/tilt_angle: frame 0: 90.00000000000001 deg is outside [-90, 90] deg");
  EXPECT_EQ(error_after(p, set_int("/particles/grains/position/step", 0, -1)),
            p + ": /particles/grains/position/step: frame 0: -1 is outside [0, 2^53]");
  EXPECT_EQ(error_after(p, set_int("/particles/grains/position/step", 1, 1LL << 60)),
            p + ": /particles/grains/position/step: frame 1: 1152921504606846976 is outside "
                "[0, 2^53]");
  EXPECT_EQ(error_after(p, set("/particles/grains/position/time", 1, -0.5)),
            p + ": /particles/grains/position/time: frame 1: -0.5 s is outside [0, inf) s");
  EXPECT_EQ(error_after(p, set("/particles/grains/box/edges", 1, -1)),
            p + ": /particles/grains/box/edges: element 1 (height): -1 m is outside [0, inf) m");
  const std::string tall = error_after(p, set("/particles/grains/box/edges", 1, 1e300));
  EXPECT_EQ(tall.rfind(p + ": /particles/grains/box/edges: element 1 (height): 1e+300 m is "
                           "outside [0, ",
                       0),
            0u)
      << tall;
  EXPECT_NE(tall.find("] m (1e8 of the largest diameter, "), std::string::npos) << tall;
  const std::string heavy = error_after(p, set("/particles/grains/mass", 2, 1e300));
  EXPECT_EQ(heavy.rfind(p + ": /particles/grains/mass: grain 2: 1e+300 kg/m is outside [", 0), 0u)
      << heavy;
  EXPECT_NE(heavy.find(" m, rho in [1e-12, 1e12] kg/m^3)"), std::string::npos) << heavy;
  const std::string spin = error_after(p, set("/particles/grains/inertia", 0, 1.0));
  EXPECT_EQ(spin.rfind(p + ": /particles/grains/inertia: grain 0: 1 kg m is outside (0, ", 0), 0u)
      << spin;
  EXPECT_NE(spin.find("] kg m (at most m r^2)"), std::string::npos) << spin;
  const std::string normal = error_after(p, set("/contacts/normal", 2 * 3, 1e300));
  std::string y;
  {
    io::Input in(p);
    char b[32];
    const double ny = h5::read<double>(in.hdf5(), "/contacts/normal", {})[7];
    y.assign(b, std::to_chars(b, b + sizeof b, ny).ptr);
  }
  EXPECT_EQ(normal, p + ": /contacts/normal: row 3: (1e+300, " + y +
                        ") is outside the unit vectors (its length is 1e+300, not 1 to within "
                        "1e-6)");
  const std::string gap = error_after(p, set("/contacts/gap", 4, -1e300));
  EXPECT_EQ(gap.rfind(p + ": /contacts/gap: row 4: -1e+300 m is outside [-1.3085", 0), 0u) << gap;
  EXPECT_NE(gap.find("] m (10 L + h times the speed bound)"), std::string::npos) << gap;
  // the per-step series: a count and an energy
  EXPECT_EQ(error_after(p, set_int("/observables/contacts/value", 1, INT64_MAX)),
            p + ": /observables/contacts/value: row 1: 9223372036854775807 is outside the "
                "integers of [0, 2^53]");
  EXPECT_EQ(error_after(p, set("/observables/kinetic_energy/value", 2, -1e-300)),
            p + ": /observables/kinetic_energy/value: row 2: -1e-300 is outside [0, inf)");
  EXPECT_EQ(error_after(p, set("/observables/tilt_angle/value", 0, -1e300)),
            p + ": /observables/tilt_angle/value: row 0: -1e+300 is outside [-90, 90]");
}
