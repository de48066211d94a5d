// The crowd strip (scenarios/output/crowd_strip.h): its schedule of frames,
// the files it writes, the people in its crops, and its row in report.html.
#include "scenarios/output/crowd_strip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "scenarios/output/png.h"
#include "scenarios/output/report.h"
#include "scenarios/output/run_outputs.h"
#include "sim/render/top_down_view.h"
#include "sim/world/world.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

constexpr double kStepS = 0.005;  // a 200 Hz physics step

// A 6 m x 6 m room, walls included, with a material for visitors.
sim::WorldDescription Room() {
  sim::WorldDescription w;
  w.name = "room";
  w.materials["floor"] =
      sim::Material{0.8, 0.0, {0.55, 0.55, 0.55, 1}, core::LaserResponse::kNormal};
  w.materials["wall"] = sim::Material{0.8, 0.0, {0.3, 0.3, 0.35, 1}, core::LaserResponse::kNormal};
  w.materials["visitor"] =
      sim::Material{0.6, 0.0, {0.85, 0.55, 0.35, 1}, core::LaserResponse::kNormal};
  w.floor = {{-3, -3}, {3, 3}, "floor", {}};
  sim::Wall room;
  room.id = "room";
  room.points_m = {{-3, -3}, {3, -3}, {3, 3}, {-3, 3}};
  room.closed = true;
  room.material = "wall";
  w.walls.push_back(room);
  return w;
}

CrowdStripOptions SixFramesOfAMinute() {
  CrowdStripOptions options;
  options.duration_s = 60.0;
  options.frames = 6;
  options.crop_m = 8.0;
  options.size_px = 240;
  return options;
}

// Stepped at the physics rate, the strip is due once at the first tick at or
// after each (k + 0.5) T / n and captures each frame once.
TEST(CrowdStripTest, FramesAtEvenlySpacedTimesEachOnce) {
  sim::World world(Room(), sim::WorldOptions{});
  CrowdStrip strip(SixFramesOfAMinute());
  for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(strip.frame_time_s(k), 5.0 + 10.0 * k);
  std::vector<double> captured_at;
  const auto ticks = static_cast<std::int64_t>(std::llround(60.0 / kStepS));
  for (std::int64_t tick = 1; tick <= ticks; ++tick) {
    const double t = static_cast<double>(tick) * kStepS;
    if (!strip.Due(t)) continue;
    strip.Capture(world, CrowdStripCentre(world), t);
    EXPECT_FALSE(strip.Due(t)) << t;
    captured_at.push_back(t);
  }
  ASSERT_EQ(captured_at.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_GE(captured_at[k], strip.frame_time_s(k) - 1e-9);
    EXPECT_LT(captured_at[k], strip.frame_time_s(k) + kStepS);
  }
  EXPECT_EQ(strip.captured(), 6);
  EXPECT_FALSE(strip.Due(1e6));

  const std::filesystem::path out = testing::TestDir();
  const std::vector<CrowdFrame> frames = strip.Write(out);
  ASSERT_EQ(frames.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    const std::string name = "snapshots/crowd_0" + std::to_string(k + 1) + ".png";
    EXPECT_EQ(frames[k].path, name);
    EXPECT_DOUBLE_EQ(frames[k].time_s, captured_at[k]);
    EXPECT_DOUBLE_EQ(frames[k].size_m, 8.0);
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
    EXPECT_EQ(std::filesystem::file_size(out / name), frames[k].png.size());
  }
}

// A capture late for several frames takes the latest one due and skips the
// earlier ones; before a frame is due, Capture does nothing.
TEST(CrowdStripTest, LateCaptureSkipsTheFramesItMissed) {
  sim::World world(Room(), sim::WorldOptions{});
  CrowdStrip strip(SixFramesOfAMinute());
  EXPECT_FALSE(strip.Due(4.9));
  strip.Capture(world, {0, 0}, 4.9);
  EXPECT_EQ(strip.captured(), 0);
  EXPECT_TRUE(strip.Due(40.0));
  strip.Capture(world, {0, 0}, 40.0);  // frames at 5, 15, 25, 35 s are due: 35 s is taken
  EXPECT_EQ(strip.captured(), 1);
  EXPECT_FALSE(strip.Due(44.9));
  EXPECT_TRUE(strip.Due(45.0));
  const std::vector<CrowdFrame> frames = strip.Write(testing::TestDir());
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].path, "snapshots/crowd_04.png");
}

// Options out of range are refused naming the field.
TEST(CrowdStripTest, ValidateNamesTheField) {
  CrowdStripOptions options = SixFramesOfAMinute();
  options.frames = 0;
  EXPECT_NE(testing::ValidateMessage(options).find("frames"), std::string::npos);
  options = SixFramesOfAMinute();
  options.duration_s = std::nan("");
  EXPECT_NE(testing::ValidateMessage(options).find("duration_s"), std::string::npos);
  options = SixFramesOfAMinute();
  options.size_px = 10;
  EXPECT_THROW(CrowdStrip{options}, std::invalid_argument);
}

// The crop is size_px square, centred on the given point: the floor's centre
// of an 8 m crop of the 6 m room is the image's centre, the walls inside.
TEST(CrowdStripTest, CropIsCentredAndSquare) {
  sim::World world(Room(), sim::WorldOptions{});
  CrowdStrip strip(SixFramesOfAMinute());
  EXPECT_TRUE(CrowdStripCentre(world).isApprox(Eigen::Vector2d(0, 0)));
  strip.Capture(world, CrowdStripCentre(world), 5.0);
  const std::vector<CrowdFrame> frames = strip.Write(testing::TestDir());
  ASSERT_EQ(frames.size(), 1u);
  // The same crop rendered directly: 240 x 240, floor grey at the centre.
  sim::TopDownOptions view;
  view.width_px = 240;
  view.window = sim::TopDownWindow{{-4, -4}, {4, 4}};
  const core::RgbImage image = sim::RenderTopDown(world, {}, view);
  EXPECT_EQ(image.width, 240);
  EXPECT_EQ(image.height, 240);
  const std::size_t centre = (120u * 240u + 120u) * 3u;
  EXPECT_EQ(image.pixels[centre], 140);  // the floor's 0.55
}

// A world with a crowd: the crop shows the present people in the colours of
// their material. Writes the crop to $PAVILION_TEST_PNG_DIR when set.
TEST(CrowdStripTest, CropShowsThePeople) {
  sim::World world(Room(), sim::WorldOptions{});
  sim::CrowdSpec spec;
  spec.options.pool_size = 30;
  spec.options.initial_present = 14;
  spec.options.max_present = 30;
  spec.options.watch_spots = 6;
  spec.entrance = {{-2.8, -2.8}, {-1.8, -2.8}, {-1.8, -1.8}, {-2.8, -1.8}};
  spec.exit = {{1.8, 1.8}, {2.8, 1.8}, {2.8, 2.8}, {1.8, 2.8}};
  spec.material = "visitor";
  world.AddCrowd(spec, 7);
  for (int i = 0; i < 400; ++i) world.Step();  // 2 s of walking
  CrowdStripOptions options = SixFramesOfAMinute();
  options.people_material = "visitor";
  options.crop_m = 6.5;
  CrowdStrip strip(options);
  strip.Capture(world, CrowdStripCentre(world), 5.0);
  const std::filesystem::path out = testing::TestDir();
  const std::vector<CrowdFrame> frames = strip.Write(out);
  ASSERT_EQ(frames.size(), 1u);
  if (const char* dir = std::getenv("PAVILION_TEST_PNG_DIR")) {
    std::filesystem::copy_file(out / frames[0].path,
                               std::filesystem::path(dir) / "crowd_strip_frame.png",
                               std::filesystem::copy_options::overwrite_existing);
    sim::TopDownOptions detail;  // the whole room, large enough to see each person's parts
    detail.width_px = 800;
    detail.people_material = "visitor";
    WritePng((std::filesystem::path(dir) / "crowd_room.png").string(),
             sim::RenderTopDown(world, {}, detail));
  }

  // Render the same crop to read its pixels: every present person's body
  // centre has one of the person's colours.
  sim::TopDownOptions view;
  view.width_px = 260;
  view.window = sim::TopDownWindow{{-3.25, -3.25}, {3.25, 3.25}};
  view.people_material = "visitor";
  const core::RgbImage image = sim::RenderTopDown(world, {}, view);
  const sim::PersonColours colours = sim::PersonColours::From({217, 140, 89});
  const std::set<std::array<std::uint8_t, 3>> person{colours.body, colours.outline, colours.legs};
  const double px_per_m = 260 / 6.5;
  int present = 0;
  for (const sim::crowd::PersonState& p : world.crowd()->people()) {
    if (!p.present) continue;
    ++present;
    const int x = static_cast<int>(std::floor((p.position_m.x() + 3.25) * px_per_m));
    const int y = static_cast<int>(std::floor((3.25 - p.position_m.y()) * px_per_m));
    const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
    const std::array<std::uint8_t, 3> c{image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
    EXPECT_TRUE(person.contains(c)) << "person at " << p.position_m.transpose();
  }
  EXPECT_GT(present, 0);
}

// report.html shows the frames in one row with their times, and nothing of
// the kind without frames.
TEST(CrowdStripTest, ReportShowsTheStripWhenFramesExist) {
  Scenario scenario;
  scenario.name = "strip";
  RunMetrics metrics;
  const std::vector<std::uint8_t> png = EncodePng(core::RgbImage(4, 4));
  ReportContent content;
  content.topdown_png = png;
  const std::string without = RenderReportHtml(scenario, metrics, content);
  EXPECT_EQ(without.find("The crowd around"), std::string::npos);
  EXPECT_EQ(without.find("<figure"), std::string::npos);
  const std::vector<CrowdFrame> frames{{"snapshots/crowd_01.png", 5.0, 8.0, png},
                                       {"snapshots/crowd_02.png", 120.0, 8.0, png},
                                       {"snapshots/crowd_03.png", 7.52, 8.0, png}};
  content.crowd_frames = frames;
  const std::string with = RenderReportHtml(scenario, metrics, content);
  EXPECT_NE(with.find("The crowd around"), std::string::npos);
  const std::size_t a = with.find("t = 5 s</figcaption>");
  const std::size_t b = with.find("t = 120 s</figcaption>");
  const std::size_t c = with.find("t = 7.5 s</figcaption>");
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(c, std::string::npos);
  EXPECT_LT(a, b);
  EXPECT_LT(b, c);
  EXPECT_NE(with.find("display:flex"), std::string::npos);
}

// The run's outputs write the strip's frames beside the other snapshots and
// show them in report.html; without a strip, no frame and no row.
TEST(CrowdStripTest, RunOutputsWriteTheStrip) {
  sim::World world(Room(), sim::WorldOptions{});
  Scenario scenario;
  scenario.name = "strip";
  scenario.world = world.description();
  RunMetrics metrics;
  CrowdStrip strip(SixFramesOfAMinute());
  for (const double t : {5.0, 15.0, 25.0}) strip.Capture(world, CrowdStripCentre(world), t);
  const std::filesystem::path out = testing::TestDir();
  WriteSnapshotsAndReport(out, scenario, world, {}, {}, {}, metrics, &strip);
  for (const char* name : {"crowd_01.png", "crowd_02.png", "crowd_03.png"}) {
    EXPECT_TRUE(std::filesystem::exists(out / "snapshots" / name)) << name;
  }
  EXPECT_FALSE(std::filesystem::exists(out / "snapshots" / "crowd_04.png"));
  std::ifstream in(out / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("t = 25 s</figcaption>"), std::string::npos);

  const std::filesystem::path plain = out / "plain";
  WriteSnapshotsAndReport(plain, scenario, world, {}, {}, {}, metrics);
  EXPECT_FALSE(std::filesystem::exists(plain / "snapshots" / "crowd_01.png"));
  std::ifstream plain_in(plain / "report.html");
  const std::string plain_html((std::istreambuf_iterator<char>(plain_in)),
                               std::istreambuf_iterator<char>());
  EXPECT_EQ(plain_html.find("<figure"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::scenarios
