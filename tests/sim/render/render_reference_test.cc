// Image regression of the off-screen renderer (sim/render/offscreen_renderer.h):
// a fixed small scene built here (a room with a box, a cylinder, an open door,
// a robot and a visitor; 160 x 120, grey and RGB) against reference pictures
// stored as binary PGM / PPM in tests/data/render/, compared with a tolerance
// so that another Mesa's rounding passes and a changed scene does not; the
// pictures are the same from renderers on concurrent threads and with more
// llvmpipe rasterizer threads (a child process of this test).
//
// To re-record the references after an intended change of the pictures:
//   PAVILION_UPDATE_RENDER_REFERENCE=1 ./build/tests/render_reference_test
// writes tests/data/render/room_gray.pgm and room_rgb.ppm (and passes); look at
// them before committing them.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/render/offscreen_renderer.h"
#include "sim/world/world.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kWidthPx = 160;
constexpr int kHeightPx = 120;
constexpr const char* kGrayReference = PAVILION_TEST_DATA_DIR "/render/room_gray.pgm";
constexpr const char* kRgbReference = PAVILION_TEST_DATA_DIR "/render/room_rgb.ppm";
constexpr const char* kUpdateVariable = "PAVILION_UPDATE_RENDER_REFERENCE";
// The child process of SameWithMoreLlvmpipeThreads: where it writes its
// pictures, and llvmpipe's thread count it renders with.
constexpr const char* kChildOutVariable = "PAVILION_RENDER_REFERENCE_CHILD_OUT";
constexpr int kChildLlvmpipeThreads = 2;

// The tolerance (per colour channel, grey levels). Another Mesa or llvmpipe
// build may round differently: a vertex's snap to the rasterizer's 1/256 px
// grid, the pixel-centre rule at a tie, an interpolated colour's last bit. A
// colour rounded differently is off by a level or two; an edge that passed
// within that rounding of pixel centres moves by one pixel, and the pixels
// along it take their neighbour's colour, off by the step between the two
// surfaces (tens of levels between this scene's objects). So: at most
// kMaxLargeFraction of the pixels (96 of 19200: a few edges' length) may be
// off by more than kLargeStepGrey, and the mean absolute difference over all
// values is at most kMaxMeanAbsGrey (a level on an eighth of the pixels and
// 0.3 % of the pixels on moved edges make about 0.35; lights two levels
// darker, a camera 5 cm aside or the door closed exceed it, see
// ToleranceSeparatesRoundingFromChange).
constexpr double kMaxMeanAbsGrey = 0.5;
constexpr int kLargeStepGrey = 24;
constexpr double kMaxLargeFraction = 0.005;

// An 8-bit picture as a file holds it: `channels` values per pixel.
struct Picture {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<std::uint8_t> values;
};

Picture FromGray(const core::GrayImage& image) {
  return {image.width, image.height, 1, image.pixels};
}
Picture FromRgb(const core::RgbImage& image) {
  return {image.width, image.height, 3, image.pixels};
}

// Binary PGM (P5, one channel) or PPM (P6, three), maxval 255.
void WritePnm(const std::string& path, const Picture& p) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out << (p.channels == 1 ? "P5" : "P6") << "\n" << p.width << " " << p.height << "\n255\n";
  out.write(reinterpret_cast<const char*>(p.values.data()),
            static_cast<std::streamsize>(p.values.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
}

// Reads what WritePnm writes (comments after the magic number allowed);
// throws std::runtime_error naming the file for anything else.
Picture ReadPnm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error(path + ": missing (record it with " + kUpdateVariable + "=1)");
  }
  std::string magic;
  in >> magic;
  Picture p;
  p.channels = magic == "P5" ? 1 : magic == "P6" ? 3 : 0;
  if (p.channels == 0) throw std::runtime_error(path + ": expected a P5 or P6 file");
  int maxval = 0;
  for (int* field : {&p.width, &p.height, &maxval}) {
    while (in >> std::ws && in.peek() == '#') in.ignore(1 << 20, '\n');
    in >> *field;
  }
  in.get();  // the single whitespace before the pixels
  if (!in || maxval != 255 || p.width < 1 || p.height < 1) {
    throw std::runtime_error(path + ": expected a width, a height and maxval 255");
  }
  p.values.resize(static_cast<std::size_t>(p.width) * p.height * p.channels);
  in.read(reinterpret_cast<char*>(p.values.data()), static_cast<std::streamsize>(p.values.size()));
  if (in.gcount() != static_cast<std::streamsize>(p.values.size())) {
    throw std::runtime_error(path + ": fewer pixels than its header says");
  }
  return p;
}

struct Difference {
  double mean_abs_grey = 0.0;   // over every channel of every pixel
  double large_fraction = 0.0;  // of pixels with a channel off by more than kLargeStepGrey
  bool Within() const {
    return mean_abs_grey <= kMaxMeanAbsGrey && large_fraction <= kMaxLargeFraction;
  }
};

std::ostream& operator<<(std::ostream& out, const Difference& d) {
  return out << "mean |difference| " << d.mean_abs_grey << ", " << 100.0 * d.large_fraction
             << " % of pixels off by more than " << kLargeStepGrey;
}

::testing::AssertionResult SameShape(const Picture& a, const Picture& b) {
  if (a.width == b.width && a.height == b.height && a.channels == b.channels) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << a.width << "x" << a.height << "x" << a.channels << " vs "
                                       << b.width << "x" << b.height << "x" << b.channels;
}

Difference Compare(const Picture& a, const Picture& b) {
  Difference d;
  long total = 0;
  int large = 0;
  for (std::size_t i = 0; i < a.values.size(); i += a.channels) {
    int worst = 0;
    for (int c = 0; c < a.channels; ++c) {
      const int step = std::abs(a.values[i + c] - b.values[i + c]);
      total += step;
      worst = std::max(worst, step);
    }
    if (worst > kLargeStepGrey) ++large;
  }
  const auto pixels = static_cast<double>(a.width) * a.height;
  d.mean_abs_grey = total / (pixels * a.channels);
  d.large_fraction = large / pixels;
  return d;
}

// The room: 8 x 6 m, its walls light, a blue crate, a red drum, a green door
// swung open, a robot and one visitor, seen from near the west wall.
struct Room {
  std::unique_ptr<World> world;
  RenderView view;
  int visitors = 0;

  explicit Room(bool door_open = true) {
    WorldDescription d;
    d.name = "reference_room";
    const auto material = [&](const std::string& name, double r, double g, double b) {
      d.materials[name] = Material{0.8, 0.0, {r, g, b, 1}, core::LaserResponse::kNormal};
    };
    material("floor", 0.45, 0.42, 0.38);
    material("wall", 0.9, 0.88, 0.8);
    material("crate", 0.15, 0.25, 0.8);
    material("drum", 0.8, 0.15, 0.1);
    material("door", 0.2, 0.6, 0.25);
    material("robot", 0.1, 0.1, 0.12);
    material("visitor", 0.7, 0.5, 0.3);
    d.floor = {{-1, -1}, {9, 7}, "floor", {}};
    Wall room;
    room.id = "room";
    room.points_m = {{0, 0}, {8, 0}, {8, 6}, {0, 6}};
    room.closed = true;
    room.material = "wall";
    d.walls.push_back(room);
    Box crate;
    crate.id = "crate";
    crate.pose = {5.5, 4.2, 0.4};
    crate.size_m = {0.8, 0.8, 1.1};
    crate.material = "crate";
    d.boxes.push_back(crate);
    Cylinder drum;
    drum.id = "drum";
    drum.position_m = {6.2, 2.2};
    drum.radius_m = 0.4;
    drum.height_m = 1.4;
    drum.material = "drum";
    d.cylinders.push_back(drum);
    Door door;
    door.id = "door";
    door.hinge_m = {7.85, 0.8};
    door.closed_yaw_rad = kPi / 2;
    door.open_yaw_rad = kPi * 0.8;
    door.open = door_open;
    door.material = "door";
    d.doors.push_back(door);
    world = std::make_unique<World>(d, WorldOptions{});
    pavilion::testing::AddRobot(*world, {"robot", pavilion::testing::PygmalionLikeModel("robot"),
                                         SystematicErrors{}, core::Pose2{4.0, 2.4, 2.2}});
    CrowdSpec crowd;
    crowd.material = "visitor";
    crowd.options.pool_size = 5;
    crowd.options.max_present = 1;
    crowd.options.watch_spots = 0;
    crowd.options.visit.group_fraction = 0.0;
    crowd.entrance = {{0.5, 0.5}, {1.0, 0.5}, {1.0, 1.0}, {0.5, 1.0}};
    crowd.exit = crowd.entrance;
    crowd.attractions = {{"crate", core::Pose2{5.0, 4.0, 0.0}, 1.0}};
    world->AddCrowd(crowd, 1);
    visitors = world->mutable_crowd()->SpawnGroup({4.8, 3.3}, 1);
    view.world_from_camera = Eigen::Translation3d(0.6, 2.8, 1.3) *
                             Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY());  // a little down
    view.intrinsics = core::CameraIntrinsics::FromHorizontalFov(kWidthPx, kHeightPx, kPi / 3);
  }
};

RenderScene PeopleInTheirMaterial() {
  RenderScene scene;
  scene.people_material = "visitor";
  return scene;
}

bool Updating() {
  const char* update = std::getenv(kUpdateVariable);
  return update != nullptr && std::string(update) == "1";
}

// Compares `actual` with the reference at `path` (or records it, see the header).
void ExpectMatchesReference(const Picture& actual, const std::string& path) {
  if (Updating()) {
    WritePnm(path, actual);
    std::cout << "recorded " << path << "\n";
    return;
  }
  const Picture reference = ReadPnm(path);
  ASSERT_TRUE(SameShape(actual, reference)) << path;
  const Difference d = Compare(actual, reference);
  EXPECT_TRUE(d.Within()) << path << ": " << d << " (at most " << kMaxMeanAbsGrey << " and "
                          << 100.0 * kMaxLargeFraction << " %)";
  ::testing::Test::RecordProperty("mean_abs_grey", std::to_string(d.mean_abs_grey));
  ::testing::Test::RecordProperty("large_fraction", std::to_string(d.large_fraction));
}

// The grey picture of the room (its visitor placed) is its reference's within
// the tolerance.
TEST(RenderReferenceTest, GrayMatchesReference) {
  const Room room;
  ASSERT_EQ(room.visitors, 1);
  OffscreenRenderer renderer;
  ExpectMatchesReference(
      FromGray(renderer.RenderGray(*room.world, room.view, PeopleInTheirMaterial())),
      kGrayReference);
}

// The RGB picture of the room is its reference's within the tolerance.
TEST(RenderReferenceTest, RgbMatchesReference) {
  const Room room;
  OffscreenRenderer renderer;
  ExpectMatchesReference(
      FromRgb(renderer.RenderRgb(*room.world, room.view, PeopleInTheirMaterial())), kRgbReference);
}

// The tolerance passes what another rounding does (one level off on every
// eighth pixel, 60 edge pixels (0.3 %) given their right neighbour's value:
// edges moved by a pixel) and fails a changed scene: the door closed, the camera
// 5 cm aside, the lights dimmed by two levels.
TEST(RenderReferenceTest, ToleranceSeparatesRoundingFromChange) {
  const Room room;
  OffscreenRenderer renderer;
  const RenderScene scene = PeopleInTheirMaterial();
  const Picture base = FromGray(renderer.RenderGray(*room.world, room.view, scene));
  Picture rounded = base;
  for (std::size_t i = 0; i < rounded.values.size(); i += 8) {
    std::uint8_t& v = rounded.values[i];
    v = v < 255 ? v + 1 : v - 1;
  }
  // The first edge pixels of the rows take their right neighbour's value.
  int moved_edge_pixels = 0;
  for (std::size_t i = 0; i + 1 < base.values.size() && moved_edge_pixels < 60; ++i) {
    if ((i + 1) % base.width == 0) continue;  // the row's last pixel
    if (std::abs(base.values[i] - base.values[i + 1]) <= kLargeStepGrey) continue;
    rounded.values[i] = base.values[i + 1];
    ++moved_edge_pixels;
  }
  ASSERT_EQ(moved_edge_pixels, 60);
  const Difference rounding = Compare(rounded, base);
  EXPECT_TRUE(rounding.Within()) << rounding;

  const Room closed(/*door_open=*/false);
  const Difference door =
      Compare(FromGray(renderer.RenderGray(*closed.world, closed.view, scene)), base);
  EXPECT_FALSE(door.Within()) << door;
  RenderView aside = room.view;
  aside.world_from_camera.translate(Eigen::Vector3d(0.0, -0.05, 0.0));
  const Difference moved = Compare(FromGray(renderer.RenderGray(*room.world, aside, scene)), base);
  EXPECT_FALSE(moved.Within()) << moved;
  Picture dimmed = base;
  for (std::uint8_t& v : dimmed.values) v = static_cast<std::uint8_t>(std::max(0, v - 2));
  const Difference darker = Compare(dimmed, base);
  EXPECT_FALSE(darker.Within()) << darker;
  RecordProperty("rounding", ::testing::PrintToString(rounding));
  RecordProperty("door_closed", ::testing::PrintToString(door));
  RecordProperty("camera_5cm_aside", ::testing::PrintToString(moved));
}

// Renderers on two threads drawing the room at the same time draw the same
// bytes, and the same as one renderer alone.
TEST(RenderReferenceTest, ConcurrentRenderersAgree) {
  const Room room;
  const RenderScene scene = PeopleInTheirMaterial();
  constexpr int kFrames = 10;
  std::vector<std::vector<core::RgbImage>> frames(2);
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      OffscreenRenderer own;
      for (int i = 0; i < kFrames; ++i)
        frames[t].push_back(own.RenderRgb(*room.world, room.view, scene));
    });
  }
  for (std::thread& t : threads) t.join();
  OffscreenRenderer alone;
  const core::RgbImage reference = alone.RenderRgb(*room.world, room.view, scene);
  for (int t = 0; t < 2; ++t) {
    ASSERT_EQ(frames[t].size(), static_cast<std::size_t>(kFrames));
    for (int i = 0; i < kFrames; ++i)
      EXPECT_EQ(frames[t][i].pixels, reference.pixels) << t << " " << i;
  }
}

// The same test binary, run again with llvmpipe rasterizing on
// kChildLlvmpipeThreads threads (set before its first context), draws the
// same bytes as this process (kDefaultLlvmpipeThreads, unless set otherwise).
TEST(RenderReferenceTest, SameWithMoreLlvmpipeThreads) {
  const Room room;
  if (const char* out = std::getenv(kChildOutVariable)) {  // the child
    ConfigureLlvmpipe(kChildLlvmpipeThreads);
    OffscreenRenderer renderer;
    WritePnm(std::string(out) + ".pgm",
             FromGray(renderer.RenderGray(*room.world, room.view, PeopleInTheirMaterial())));
    WritePnm(std::string(out) + ".ppm",
             FromRgb(renderer.RenderRgb(*room.world, room.view, PeopleInTheirMaterial())));
    return;
  }
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("render_reference_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "child").string();
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::string command = std::string(kChildOutVariable) + "=" + pavilion::testing::ShellQuote(out);
  command.append(" ").append(pavilion::testing::ShellQuote(self));
  command.append(" --gtest_filter=RenderReferenceTest.SameWithMoreLlvmpipeThreads");
  command.append(" >").append(pavilion::testing::ShellQuote((dir / "child.log").string()));
  command.append(" 2>&1");
  const int status = std::system(command.c_str());
  ASSERT_TRUE(status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << pavilion::testing::ReadTextFile(dir / "child.log");
  OffscreenRenderer renderer;
  EXPECT_EQ(ReadPnm(out + ".pgm").values,
            renderer.RenderGray(*room.world, room.view, PeopleInTheirMaterial()).pixels);
  EXPECT_EQ(ReadPnm(out + ".ppm").values,
            renderer.RenderRgb(*room.world, room.view, PeopleInTheirMaterial()).pixels);
  EXPECT_NE(LlvmpipeThreads(), kChildLlvmpipeThreads);  // else the child tested nothing new
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pavilion::sim
