#include "fit/basis_benchmark.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fit/test_databases.h"
#include "normals/sphere_geometry.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

}  // namespace

// The reference cache is reused only for the very scene it was rendered for:
// another sample count renders anew, and so does a damaged file.
TEST(BasisBenchmark, TheReferenceCacheIsReusedOnlyWhenItMatchesAndIntact) {
  const BasisDatabase db = LoadDatabase(DemoStandins());
  cv::Mat sky(16, 32, CV_32FC3);
  cv::randu(sky, cv::Scalar::all(0.1), cv::Scalar::all(2.0));
  const LatLongProbe probe(sky, "sky");
  const PixelGeometry g = OrthographicSphere(8, 80);
  const std::string path = (fs::temp_directory_path() / "brdfshot_reference_cache_test.bsbi").string();
  fs::remove(path);

  double first = -1, again = -1, other = -1;
  const BasisImages a = LoadOrRenderReference(path, g, probe, db, {0, 3}, {8, 12}, false, &first);
  const auto written = fs::last_write_time(path);
  const BasisImages b = LoadOrRenderReference(path, g, probe, db, {0, 3}, {8, 12}, false, &again);
  EXPECT_EQ(fs::last_write_time(path), written) << "a matching cache is not rewritten";
  EXPECT_EQ(again, first) << "its render time comes from its header";
  for (int c = 0; c < 3; ++c) EXPECT_EQ((a.Y[c] - b.Y[c]).norm(), 0);

  const BasisImages finer = LoadOrRenderReference(path, g, probe, db, {0, 3}, {12, 16}, false, &other);
  EXPECT_EQ(finer.header.at("samples"), nlohmann::json({12, 16}));
  EXPECT_GT((finer.Y[1] - a.Y[1]).norm(), 0) << "rendered anew with the finer samples";

  fs::resize_file(path, fs::file_size(path) / 2);
  const BasisImages repaired = LoadOrRenderReference(path, g, probe, db, {0, 3}, {12, 16}, false, &other);
  for (int c = 0; c < 3; ++c) EXPECT_EQ((repaired.Y[c] - finer.Y[c]).norm(), 0);
  EXPECT_NO_THROW(BasisImages::Read(path)) << "the damaged file was replaced";
  fs::remove(path);
}

}  // namespace brdfshot
