#include "fit/nbrdf.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "fit/npy.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {
// The data folder's networks, else the repository's own copy.
std::string NpyDir() {
  std::error_code ec;
  for (const std::string& d : {DataPath("merl-nbrdf/npy"), RepoDataPath("merl-nbrdf/npy")})
    if (!d.empty() && fs::is_directory(d, ec)) return d;
  return "";
}

// Independent scalar forward pass: reads the float payload after the header's
// newline by hand and runs the MLP with plain loops in double.
std::vector<float> RawFloats(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t start = bytes.find('\n') + 1;
  std::vector<float> v((bytes.size() - start) / 4);
  std::memcpy(v.data(), bytes.data() + start, v.size() * 4);
  return v;
}

std::array<double, 3> ScalarNbrdf(const std::string& dir, const std::string& name, const HalfDiff& hd) {
  auto f = [&](const char* s) { return RawFloats(dir + "/" + name + s); };
  const auto w1 = f("_fc1.npy"), b1 = f("_b1.npy"), w2 = f("_fc2.npy"), b2 = f("_b2.npy"), w3 = f("_fc3.npy"),
             b3 = f("_b3.npy");
  const double st = std::sin(hd.theta_d);
  const double x[6] = {std::sin(hd.theta_h), 0, std::cos(hd.theta_h), st * std::cos(hd.phi_d), st * std::sin(hd.phi_d),
                       std::cos(hd.theta_d)};
  double h1[21], h2[21];
  for (int o = 0; o < 21; ++o) {
    double s = b1[o];
    for (int i = 0; i < 6; ++i) s += x[i] * w1[i * 21 + o];
    h1[o] = s > 0 ? s : 0;
  }
  for (int o = 0; o < 21; ++o) {
    double s = b2[o];
    for (int i = 0; i < 21; ++i) s += h1[i] * w2[i * 21 + o];
    h2[o] = s > 0 ? s : 0;
  }
  std::array<double, 3> out;
  for (int o = 0; o < 3; ++o) {
    double s = b3[o];
    for (int i = 0; i < 21; ++i) s += h2[i] * w3[i * 3 + o];
    out[o] = std::max(0.0, std::exp(s) - 1);
  }
  return out;
}
}  // namespace

TEST(Nbrdf, BatchedAndWrittenTableMatchAnIndependentScalarPass) {
  const std::string dir = NpyDir();
  if (dir.empty()) GTEST_SKIP() << "no merl-nbrdf data";
  const MerlGrid grid{30, 30, 60};
  for (const std::string name : {"chrome", "blue-fabric"}) {
    const NbrdfNetwork net = NbrdfNetwork::Load(dir, name);
    const MerlBrdf table = NbrdfToMerl(net, grid);
    const std::string path = fs::temp_directory_path() / ("brdfshot_nb_" + std::to_string(::getpid()) + ".binary");
    table.Write(path);
    const MerlBrdf back = MerlBrdf::Read(path);
    fs::remove(path);
    int checked = 0;
    for (int i : {0, 3, 11, 20, 29})
      for (int j : {1, 10, 25})
        for (int k : {0, 17, 45}) {
          const size_t idx = grid.Index(i, j, k);
          if (!grid.Measurable(idx)) continue;
          const HalfDiff hd = grid.LatticePoint(i, j, k);
          const auto want = ScalarNbrdf(dir, name, hd);
          const Rgb batched = net.EvalHalfDiff(hd);
          for (int c = 0; c < 3; ++c) {
            const double tol = 1e-5 * want[c] + 1e-7;
            EXPECT_NEAR(batched[c], want[c], tol) << name << " " << i << "," << j << "," << k;
            EXPECT_NEAR(back.Value(c, idx), want[c], tol) << name << " file";
          }
          ++checked;
        }
    EXPECT_GT(checked, 20);
  }
}

TEST(Nbrdf, ClampingLeavesNoNegativeMeasuredEntry) {
  const std::string dir = NpyDir();
  if (dir.empty()) GTEST_SKIP() << "no merl-nbrdf data";
  const MerlGrid grid{20, 20, 40};
  for (const std::string name : {"black-obsidian", "chrome", "white-paint"}) {
    const MerlBrdf t = NbrdfToMerl(NbrdfNetwork::Load(dir, name), grid);
    for (size_t idx = 0; idx < grid.size(); ++idx) {
      if (!grid.Measurable(idx)) continue;
      for (int c = 0; c < 3; ++c) ASSERT_GE(t.raw(c, idx), 0.0) << name;
    }
  }
}

class NpyBadFileTest : public ::testing::Test {
 protected:
  static std::string Npy(const std::string& descr, const std::string& shape, size_t floats,
                         const std::string& magic = "\x93NUMPY") {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::string s = magic + std::string("\x01\x00", 2);
    s += static_cast<char>(header.size() & 0xff);
    s += static_cast<char>(header.size() >> 8);
    return s + header + std::string(floats * 4, '\0');
  }
  void Expect(const std::string& bytes, const std::string& fragment) {
    try {
      ParseNpyFloat32(bytes, "weights.npy");
      ADD_FAILURE() << "expected error: " << fragment;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("weights.npy"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
};

TEST_F(NpyBadFileTest, GoodFileParses) {
  const NpyArray a = ParseNpyFloat32(Npy("<f4", "(6, 21)", 126), "w.npy");
  ASSERT_EQ(a.shape.size(), 2u);
  EXPECT_EQ(a.shape[0], 6u);
  EXPECT_EQ(a.data.size(), 126u);
}
TEST_F(NpyBadFileTest, WrongMagic) { Expect(Npy("<f4", "(3,)", 3, "\x93NUMPX"), "magic"); }
TEST_F(NpyBadFileTest, WrongDtype) { Expect(Npy("<f8", "(3,)", 6), "dtype"); }
TEST_F(NpyBadFileTest, Truncated) { Expect(Npy("<f4", "(6, 21)", 100), "truncated"); }
TEST(NpyShape, WrongShapeForTheNetworkIsNamed) {
  const std::string dir = fs::temp_directory_path() / ("brdfshot_npy_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string src = NpyDir();
  if (src.empty()) GTEST_SKIP() << "no merl-nbrdf data";
  for (const char* s : {"_fc1", "_b1", "_fc2", "_b2", "_fc3", "_b3"})
    fs::copy_file(src + "/chrome" + s + ".npy", dir + "/x" + s + ".npy");
  fs::copy_file(src + "/chrome_b1.npy", dir + "/x_fc1.npy", fs::copy_options::overwrite_existing);
  try {
    NbrdfNetwork::Load(dir, "x");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x_fc1.npy"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("shape"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace brdfshot
