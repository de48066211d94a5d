// People in the top-down view (sim/render/top_down_view.h): shoulder disc,
// legs at the section, heading tick; parked people not drawn; crops.
#include "sim/render/top_down_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/world/world.h"

namespace pavilion::sim {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kBackground{250, 250, 250};
// 100 px per m: a person's parts are several pixels apart.
constexpr double kPxPerM = 100.0;
constexpr int kSizePx = 400;  // the picture spans [0, 4] m in x and y
const TopDownFrame kFrame{{0.0, 4.0}, kPxPerM};

Rgb PixelAt(const core::RgbImage& image, const Eigen::Vector2d& p_m) {
  const int x = static_cast<int>(std::floor((p_m.x() - kFrame.top_left_m.x()) * kPxPerM));
  const int y = static_cast<int>(std::floor((kFrame.top_left_m.y() - p_m.y()) * kPxPerM));
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

int CountNot(const core::RgbImage& image, const Rgb& c) {
  int n = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 3) {
    if (image.pixels[i] != c[0] || image.pixels[i + 1] != c[1] || image.pixels[i + 2] != c[2]) ++n;
  }
  return n;
}

// A person mid-stride (legs apart fore and aft) at `position`, facing `heading`.
crowd::PersonState Walker(const Eigen::Vector2d& position_m, double heading_rad) {
  crowd::PersonState p;
  p.position_m = position_m;
  p.heading_rad = heading_rad;
  p.present = true;
  p.gait.phase_rad = std::numbers::pi / 2;
  p.gait.swing_m = 0.15;
  return p;
}

core::RgbImage Blank() { return core::RgbImage(kSizePx, kSizePx, 250, 250, 250); }

// The body centre has the disc's colour and both legs, where the section
// cuts them, the legs' colour: a person reads as a body standing on two legs.
TEST(TopDownPeopleTest, BodyAndLegsInThePersonsColours) {
  const PersonColours colours = PersonColours::From(kPersonRgb);
  for (const double heading : {0.0, 1.0, 2.5, -2.0}) {
    const crowd::PersonState p = Walker({2.0, 2.0}, heading);
    core::RgbImage image = Blank();
    DrawPeople({p}, 0.5, colours, kFrame, &image);
    EXPECT_EQ(PixelAt(image, p.position_m), colours.body) << heading;
    for (const Eigen::Vector2d& leg : p.LegCentres(0.5)) {
      EXPECT_EQ(PixelAt(image, leg), colours.legs) << heading;
    }
    // Nothing beyond the heading tick's reach.
    const double reach = 1.6 * p.shape.radius_m;
    for (const Eigen::Vector2d& far :
         {Eigen::Vector2d(2.0 + reach, 2.0), Eigen::Vector2d(2.0 - reach, 2.0),
          Eigen::Vector2d(2.0, 2.0 + reach), Eigen::Vector2d(2.0, 2.0 - reach)}) {
      EXPECT_EQ(PixelAt(image, far), kBackground) << heading;
    }
  }
  // The three colours differ from each other and from the background.
  EXPECT_NE(colours.body, colours.legs);
  EXPECT_NE(colours.body, colours.outline);
  EXPECT_NE(colours.legs, colours.outline);
  EXPECT_NE(colours.body, kBackground);
}

// The legs follow the section height: cut at the picture's height below the
// hip, at kPeopleLegCutM when the picture's cut passes above it.
TEST(TopDownPeopleTest, LegsCutAtTheSectionOrBelowTheHip) {
  const PersonColours colours = PersonColours::From(kPersonRgb);
  const crowd::PersonState p = Walker({2.0, 2.0}, 0.0);
  core::RgbImage low = Blank();
  DrawPeople({p}, 0.1, colours, kFrame, &low);
  for (const Eigen::Vector2d& leg : p.LegCentres(0.1)) EXPECT_EQ(PixelAt(low, leg), colours.legs);
  core::RgbImage high = Blank();
  DrawPeople({p}, 1.2, colours, kFrame, &high);
  for (const Eigen::Vector2d& leg : p.LegCentres(kPeopleLegCutM)) {
    EXPECT_EQ(PixelAt(high, leg), colours.legs);
  }
}

// A parked person (not on the floor) leaves the picture untouched.
TEST(TopDownPeopleTest, ParkedPersonDrawsNothing) {
  crowd::PersonState p = Walker({2.0, 2.0}, 0.3);
  p.present = false;
  core::RgbImage image = Blank();
  DrawPeople({p, p}, 0.5, PersonColours::From(kPersonRgb), kFrame, &image);
  EXPECT_EQ(CountNot(image, kBackground), 0);
}

// The heading tick crosses the disc's edge on the forward side only.
TEST(TopDownPeopleTest, HeadingTickOnTheForwardSide) {
  const PersonColours colours = PersonColours::From(kPersonRgb);
  for (int k = 0; k < 8; ++k) {
    const double heading = 2.0 * std::numbers::pi * k / 8 + 0.1;
    const crowd::PersonState p = Walker({2.0, 2.0}, heading);
    core::RgbImage image = Blank();
    DrawPeople({p}, 0.5, colours, kFrame, &image);
    const Eigen::Vector2d forward(std::cos(heading), std::sin(heading));
    const double r = p.shape.radius_m;
    EXPECT_EQ(PixelAt(image, p.position_m + 1.25 * r * forward), colours.outline) << heading;
    EXPECT_EQ(PixelAt(image, p.position_m - 1.25 * r * forward), kBackground) << heading;
    EXPECT_EQ(PixelAt(image, p.position_m + 0.75 * r * forward), colours.outline) << heading;
    EXPECT_EQ(PixelAt(image, p.position_m - 0.75 * r * forward), colours.body) << heading;
  }
}

// Hundreds of people, some of them partly outside, are drawn clipped.
TEST(TopDownPeopleTest, ManyPeopleClipAtTheBorder) {
  std::vector<crowd::PersonState> people;
  for (int i = 0; i < 300; ++i) {
    people.push_back(Walker({-0.5 + 0.017 * i, -0.1 + 0.015 * i}, 0.05 * i));
  }
  core::RgbImage image = Blank();
  DrawPeople(people, 0.5, PersonColours::From(kPersonRgb), kFrame, &image);
  EXPECT_GT(CountNot(image, kBackground), 1000);
}

// A 6 m x 6 m room with a pillar, for crops.
WorldDescription Room() {
  WorldDescription w;
  w.name = "room";
  w.materials["floor"] = Material{0.8, 0.0, {0.5, 0.5, 0.5, 1}, core::LaserResponse::kNormal};
  w.materials["wall"] = Material{0.8, 0.0, {0.2, 0.2, 0.6, 1}, core::LaserResponse::kNormal};
  w.floor = {{0, 0}, {6, 6}, "floor"};
  Wall room;
  room.id = "room";
  room.points_m = {{0, 0}, {6, 0}, {6, 6}, {0, 6}};
  room.closed = true;
  room.material = "wall";
  w.walls.push_back(room);
  w.cylinders.push_back({"pillar", {4, 4}, 0.3, 2.0, 0.0, "wall"});
  return w;
}

// A window draws that part of the world at the asked width, square for a
// square window: the pillar lands at the crop's centre.
TEST(TopDownViewTest, WindowCropsTheWorld) {
  World world(Room(), WorldOptions{});
  TopDownOptions view;
  view.width_px = 200;
  view.window = TopDownWindow{{3, 3}, {5, 5}};
  const core::RgbImage image = RenderTopDown(world, {}, view);
  EXPECT_EQ(image.width, 200);
  EXPECT_EQ(image.height, 200);
  const std::size_t centre = (100u * 200u + 100u) * 3u;
  EXPECT_EQ(image.pixels[centre + 2], 153);  // the pillar's blue (0.6)
  view.window = TopDownWindow{{3, 3}, {3, 5}};
  EXPECT_THROW(RenderTopDown(world, {}, view), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::sim
