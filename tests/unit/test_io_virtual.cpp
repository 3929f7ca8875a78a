// Virtual datasets (io/h5.hpp, write_virtual): to-xdmf's per-frame arrays read a run's rows
// in place through them (io/xdmf.hpp), so a reader in another folder, given the virtual
// file's path, must get the source's values, with zeros where no block maps.
#include "scratch_dir.hpp"
#include "cdpile/error.hpp"
#include "cdpile/io/h5.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace cdpile;
namespace h5 = cdpile::io::h5;


TEST(Virtual, AFrameOfAStackReadsInPlaceWithZerosWhereNothingMaps) {
  const ScratchDir s("vds");
  fs::create_directories(s.dir / "runs");
  fs::create_directories(s.dir / "views");
  {  // a run-like stack: 3 frames x 2 grains x (x, y), and 5 contact rows
    h5::File src = h5::create((s.dir / "runs/run.h5").string(), "run.h5");
    std::vector<double> pos(12);
    for (std::size_t k = 0; k < pos.size(); ++k) pos[k] = 0.5 * static_cast<double>(k);
    h5::write(src, "/p", pos.data(), {3, 2, 2});
    std::vector<std::int32_t> rows{7, 8, 9, 10, 11};
    h5::write(src, "/c", rows);
    h5::File side = h5::create((s.dir / "views/side.hdf5").string(), "side.hdf5");
    // frame 1 as a [2 x 3] array: x, y, then z = 0; rows 1-3 of /c after two zeros
    h5::write_virtual(side, "/frames/1/xyz", {2, 3}, src, "../runs/run.h5",
                      {{"/p", {1, 0, 0}, {1, 2, 2}, {0, 0}, {2, 2}}});
    h5::write_virtual(side, "/rows", {5}, src, "../runs/run.h5", {{"/c", {1}, {3}, {2}, {3}}});
  }
  // read from elsewhere: the source is found beside the virtual file, not the working folder
  const fs::path here = fs::current_path();
  fs::current_path(s.dir);
  const h5::File side = h5::open_read((s.dir / "views/side.hdf5").string(), "side.hdf5");
  const auto xyz = h5::read<double>(side, "/frames/1/xyz", {2, 3});
  const auto rows = h5::read<std::int32_t>(side, "/rows", {5});
  fs::current_path(here);
  EXPECT_EQ(xyz, (std::vector<double>{2.0, 2.5, 0.0, 3.0, 3.5, 0.0}));
  EXPECT_EQ(rows, (std::vector<std::int32_t>{0, 0, 8, 9, 10}));
}

TEST(Virtual, AMissingSourceDatasetIsAnErrorNamingIt) {
  const ScratchDir s("vds");
  h5::File src = h5::create((s.dir / "run.h5").string(), "run.h5");
  h5::File side = h5::create((s.dir / "side.hdf5").string(), "side.hdf5");
  try {
    h5::write_virtual(side, "/v", {2}, src, "run.h5", {{"/nothing", {0}, {2}, {0}, {2}}});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "run.h5: /nothing: missing dataset");
  }
}
