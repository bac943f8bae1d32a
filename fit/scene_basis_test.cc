#include "fit/scene_basis.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include "fit/test_databases.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/image_io.h"

namespace brdfshot {
namespace {

namespace fs = std::filesystem;

SceneBasisOptions DemoScene(const std::string& probe) {
  SceneBasisOptions o;
  o.probe = probe;
  o.sphere = 16;
  o.quality.theta_samples = 8;
  o.quality.phi_samples = 12;
  o.database = DemoStandins();
  return o;
}

// A random 32 × 16 sky (radiance 0.1 … 2), the probe of these small scenes.
cv::Mat RandomSky() {
  cv::Mat sky(16, 32, CV_32FC3);
  cv::randu(sky, cv::Scalar::all(0.1), cv::Scalar::all(2.0));
  return sky;
}

}  // namespace

// Light transport is linear in the lighting: the same scene under a probe of
// twice the radiance has twice every basis image. The header names what the
// images are of, so a later fit can refuse images of another scene.
TEST(SceneBasis, ImagesAreLinearInTheProbeAndTheHeaderNamesTheScene) {
  const fs::path dir = fs::temp_directory_path() / "brdfshot_scene_basis_test";
  fs::create_directories(dir);
  const cv::Mat sky = RandomSky();
  const std::string one = (dir / "one.exr").string(), two = (dir / "two.exr").string();
  WriteExr(one, sky);
  WriteExr(two, cv::Mat(sky * 2));
  const SceneBasis a = ComputeSceneBasis(DemoScene(one)), b = ComputeSceneBasis(DemoScene(two));
  const uint64_t one_hash = LatLongProbe::Read(one).Hash();
  fs::remove_all(dir);

  ASSERT_EQ(a.images.Y[0].cols(), a.bases);
  EXPECT_EQ(a.bases, 3 * 16) << "the 16 demo stand-ins, three channels each";
  EXPECT_EQ(a.images.geometry.size(), OrthographicSphere(16, 80).size());
  for (int c = 0; c < 3; ++c) {
    ASSERT_GT(a.images.Y[c].norm(), 0);
    EXPECT_LT((b.images.Y[c] - 2 * a.images.Y[c]).norm(), 1e-5 * b.images.Y[c].norm()) << "channel " << c;
  }
  const nlohmann::json& h = a.images.header;
  EXPECT_EQ(h.at("probe"), one);
  EXPECT_EQ(h.at("probe_hash"), one_hash);
  EXPECT_NE(h.at("probe_hash"), b.images.header.at("probe_hash"));
  EXPECT_EQ(h.at("geometry_hash"), a.images.geometry.Hash());
  EXPECT_EQ(h.at("bases").size(), static_cast<size_t>(a.bases));
  EXPECT_EQ(h.at("geometry"), "orthographic-sphere");
  EXPECT_FALSE(a.search.has_value());
  // The analytic baseline's lobes are rendered with them, as linear.
  ASSERT_TRUE(a.images.has_lobes());
  EXPECT_EQ(a.images.lobes[0].cols(), a.images.Lobes("a").columns());
  for (int c = 0; c < 3; ++c)
    EXPECT_LT((b.images.lobes[c] - 2 * a.images.lobes[c]).norm(), 1e-5 * b.images.lobes[c].norm()) << "channel " << c;
}

// The file keeps the lobe images beside the basis images; one without lobes
// still reads; a file cut short is refused with its name.
TEST(SceneBasis, LobeImagesRoundTripThroughTheFileAndACutFileIsRefused) {
  const fs::path dir = fs::temp_directory_path() / "brdfshot_scene_basis_lobes_test";
  fs::remove_all(dir);  // a run cut short leaves its pipe behind
  fs::create_directories(dir);
  const std::string probe = (dir / "sky.exr").string(), file = (dir / "b.bsbi").string();
  WriteExr(probe, RandomSky());
  BasisImages a = ComputeSceneBasis(DemoScene(probe)).images;
  a.Write(file);
  const BasisImages back = BasisImages::Read(file);
  ASSERT_TRUE(back.has_lobes());
  EXPECT_TRUE(back.Lobes(file) == LambertGgxLobes{});
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(back.Y[c], a.Y[c]);
    EXPECT_EQ(back.lobes[c], a.lobes[c]);
  }
  const std::string bytes = ReadFileBytes(file);
  try {
    BasisImages::Parse(bytes.substr(0, bytes.size() - 4), file);
    ADD_FAILURE() << "a cut file was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
  // A pipe has no size to map: it is read like a stream, to the same images.
  const std::string fifo = (dir / "b.fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A reader that stops early then fails the test, not the process.
  std::signal(SIGPIPE, SIG_IGN);
  std::atomic<bool> written{false};
  std::thread writer([&] {
    std::ofstream(fifo, std::ios::binary) << bytes;
    written = true;
  });
  BasisImages piped;
  try {
    piped = BasisImages::Read(fifo);
  } catch (const std::exception& e) {
    // The writer may still wait for a reader to open the pipe, or for room
    // in it: hold a read end open and drain it until the thread ends, so
    // that the test reports the failure instead of hanging.
    const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    char sink[1 << 16];
    while (fd >= 0 && !written) {
      if (::read(fd, sink, sizeof sink) <= 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (fd >= 0) ::close(fd);
    writer.join();
    FAIL() << "reading the basis images through a pipe: " << e.what();
  }
  writer.join();
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(piped.Y[c], a.Y[c]);
    EXPECT_EQ(piped.lobes[c], a.lobes[c]);
  }
  for (auto& L : a.lobes) L.resize(L.rows(), 0);
  a.header.erase("lobes");
  a.Write(file);
  EXPECT_FALSE(BasisImages::Read(file).has_lobes());
  // Asked for without lobes: the same bases, no lobe images, no lobe header.
  SceneBasisOptions without = DemoScene(probe);
  without.lobes = false;
  const BasisImages bare = ComputeSceneBasis(without).images;
  EXPECT_FALSE(bare.has_lobes());
  EXPECT_FALSE(bare.header.contains("lobes"));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(bare.Y[c], back.Y[c]);
  fs::remove_all(dir);
}

// Captures of an identical scene share one rendering: the second is taken
// from the shared folder, equal to what rendering gives; another probe is
// rendered anew; a damaged shared file is not trusted but re-rendered.
TEST(SceneBasis, IdenticalScenesShareOneRenderingAndADamagedShareIsRenderedAgain) {
  const fs::path dir = fs::temp_directory_path() / "brdfshot_scene_basis_shared_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const cv::Mat sky = RandomSky();
  const std::string one = (dir / "one.exr").string(), two = (dir / "two.exr").string();
  WriteExr(one, sky);
  WriteExr(two, cv::Mat(sky * 0.5));
  SceneBasisOptions o = DemoScene(one);
  o.shared_dir = (dir / "shared").string();
  const SceneBasis unshared = ComputeSceneBasis(DemoScene(one));
  // The first with an output of its own: the shared file is that output, linked.
  const std::string first_out = (dir / "first.bsbi").string(), second_out = (dir / "second.bsbi").string();
  const SceneBasis first = ComputeSceneBasis(o, first_out), second = ComputeSceneBasis(o, second_out);
  const bool linked = fs::equivalent(first_out, first.shared_file);
  const BasisImages first_written = BasisImages::Read(first_out), second_written = BasisImages::Read(second_out);
  const BasisImages first_shared = BasisImages::Read(first.shared_file);
  SceneBasisOptions other = o;
  other.probe = two;
  const SceneBasis under_two = ComputeSceneBasis(other);
  SceneBasisOptions bare = o;
  bare.lobes = false;
  const SceneBasis without_lobes = ComputeSceneBasis(bare);
  std::filesystem::resize_file(first.shared_file, fs::file_size(first.shared_file) / 2);
  const SceneBasis after_damage = ComputeSceneBasis(o), after_repair = ComputeSceneBasis(o);
  fs::remove_all(dir);

  EXPECT_FALSE(unshared.reused);
  EXPECT_FALSE(first.reused);
  EXPECT_TRUE(second.reused);
  EXPECT_EQ(second.shared_file, first.shared_file);
  EXPECT_FALSE(under_two.reused) << "another probe is another scene";
  EXPECT_FALSE(without_lobes.reused) << "images without lobes are another file";
  EXPECT_FALSE(without_lobes.images.has_lobes());
  EXPECT_NE(without_lobes.shared_file, first.shared_file);
  EXPECT_NE(under_two.shared_file, first.shared_file);
  EXPECT_FALSE(after_damage.reused) << "a truncated shared file must be rendered again";
  EXPECT_TRUE(after_repair.reused) << "and the rendering stored again";
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(first.images.Y[c], unshared.images.Y[c]) << "sharing changes no image, channel " << c;
    EXPECT_EQ(second.images.Y[c], unshared.images.Y[c]) << "channel " << c;
    EXPECT_EQ(after_damage.images.Y[c], unshared.images.Y[c]) << "channel " << c;
  }
  EXPECT_EQ(second.images.header.at("probe"), one);
  EXPECT_TRUE(linked) << "a file system that has hard links shares the output, not a second write";
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(first_written.Y[c], unshared.images.Y[c]) << "the output holds the images, channel " << c;
    EXPECT_EQ(first_shared.Y[c], unshared.images.Y[c]) << "channel " << c;
    EXPECT_EQ(second_written.Y[c], unshared.images.Y[c]) << "a reused scene's output too, channel " << c;
    EXPECT_EQ(first_written.lobes[c], first.images.lobes[c]) << "channel " << c;
  }
  EXPECT_EQ(second_written.header.at("probe"), one);
  EXPECT_EQ(second.images.header.at("quality"), unshared.images.header.at("quality"));
}

}  // namespace brdfshot
