// People in the top-down view (sim/render/top_down_view.h): shoulder disc,
// legs at the section, heading tick; parked people not drawn; crops; the
// picture's frame and the legend of what it draws.
#include "sim/render/top_down_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
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
  w.floor = {{0, 0}, {6, 6}, "floor", {}};
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

std::vector<std::string> Labels(const std::vector<TopDownLegendItem>& items) {
  std::vector<std::string> labels;
  for (const TopDownLegendItem& i : items) labels.push_back(i.label);
  return labels;
}

// The frame puts the floor's corner plus the margin at the top left, at the
// picture's width over the drawn width: a wall's pixel lands where it says.
TEST(TopDownViewTest, FrameLocatesTheWorldInThePicture) {
  World world(Room(), WorldOptions{});
  TopDownOptions view;
  view.width_px = 700;  // 7 m drawn: 100 px per m
  const TopDownFrame frame = TopDownFrameOf(world, view);
  EXPECT_DOUBLE_EQ(frame.px_per_m, 100.0);
  EXPECT_DOUBLE_EQ(frame.top_left_m.x(), -0.5);
  EXPECT_DOUBLE_EQ(frame.top_left_m.y(), 6.5);
  const core::RgbImage image = RenderTopDown(world, {}, view);
  // The pillar's centre (4, 4) at pixel (450, 250): the wall material's blue.
  const std::size_t i = (250u * 700u + 450u) * 3u;
  EXPECT_EQ(image.pixels[i + 2], 153);
  view.window = TopDownWindow{{1, 1}, {3, 2}};
  EXPECT_DOUBLE_EQ(TopDownFrameOf(world, view).px_per_m, 350.0);
  EXPECT_DOUBLE_EQ(TopDownFrameOf(world, view).top_left_m.y(), 2.0);
}

// The legend lists each labelled track that is drawn (two points or more)
// once, in order, and nothing for unlabelled or single-point tracks.
TEST(TopDownLegendTest, ListsTheDrawnLabelledTracksOnce) {
  World world(Room(), WorldOptions{});
  const std::vector<Eigen::Vector2d> path{{1, 1}, {2, 2}};
  std::vector<TopDownTrack> tracks{{path, {20, 60, 220}, 0.9, 1.0, "true path"},
                                   {{{1, 1}}, {230, 150, 20}, 0.8, 1.0, "odometry"},
                                   {path, {1, 2, 3}},
                                   {path, {30, 160, 60}, 0.7, 2.0, "estimate"},
                                   {path, {20, 60, 220}, 0.9, 1.0, "true path"}};
  const std::vector<TopDownLegendItem> items = TopDownLegend(world, tracks, TopDownOptions{});
  EXPECT_EQ(Labels(items), (std::vector<std::string>{"true path", "estimate"}));
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[1].item, TopDownItem::kTrack);
  EXPECT_EQ(items[1].rgb, (Rgb{30, 160, 60}));
  EXPECT_DOUBLE_EQ(items[1].alpha, 0.7);
  EXPECT_DOUBLE_EQ(items[1].width_px, 2.0);
  EXPECT_TRUE(TopDownLegend(world, {}, TopDownOptions{}).empty());
}

// Places are listed when drawn (draw_places), an area before the tracks (it
// lies under them) and a pose after; a body only while inside the picture.
TEST(TopDownLegendTest, PlacesAndBodiesWhenDrawn) {
  WorldDescription d = Room();
  Place place;
  place.pose = core::Pose2(1.0, 1.0, 0.0);
  place.area = core::Polygon2{{0.5, 0.5}, {1.5, 0.5}, {1.5, 1.5}, {0.5, 1.5}};
  d.places["desk"] = place;
  World world(d, WorldOptions{});
  BodySpec box;
  box.id = "crate";
  box.shape.type = BodyShapeType::kBox;
  box.pose = core::Pose2(2.0, 5.0, 0.0);
  box.material = "wall";
  world.AddBody(box);
  const std::vector<TopDownTrack> tracks{{{{1, 1}, {2, 2}}, {20, 60, 220}, 0.9, 1.0, "true path"}};
  TopDownOptions view;
  EXPECT_EQ(Labels(TopDownLegend(world, tracks, view)),
            (std::vector<std::string>{"place area", "true path", "body", "place"}));
  view.draw_places = false;
  EXPECT_EQ(Labels(TopDownLegend(world, tracks, view)),
            (std::vector<std::string>{"true path", "body"}));
  view.window = TopDownWindow{{0, 0}, {1.5, 1.5}};  // the crate lies beyond
  EXPECT_EQ(Labels(TopDownLegend(world, tracks, view)), (std::vector<std::string>{"true path"}));
}

// Present people are listed as "visitor" in the colours DrawPeople uses
// (the people's material); a crowd none of whose people is present, not.
TEST(TopDownLegendTest, VisitorsWhilePresent) {
  WorldDescription d = Room();
  d.materials["visitor"] = Material{0.6, 0.0, {0.8, 0.4, 0.2, 1}, core::LaserResponse::kNormal};
  for (const int present : {0, 6}) {
    World world(d, WorldOptions{});
    CrowdSpec spec;
    spec.options.pool_size = 8;
    spec.options.initial_present = present;
    spec.options.max_present = 8;
    spec.options.watch_spots = 4;
    spec.entrance = {{0.2, 0.2}, {1.0, 0.2}, {1.0, 1.0}, {0.2, 1.0}};
    spec.exit = {{5.0, 5.0}, {5.8, 5.0}, {5.8, 5.8}, {5.0, 5.8}};
    spec.material = "visitor";
    world.AddCrowd(spec, 3);
    TopDownOptions view;
    view.people_material = "visitor";
    const std::vector<TopDownLegendItem> items = TopDownLegend(world, {}, view);
    if (present == 0) {
      EXPECT_TRUE(items.empty());
      continue;
    }
    ASSERT_EQ(Labels(items), std::vector<std::string>{"visitor"});
    const PersonColours colours = PersonColours::From({204, 102, 51});
    EXPECT_EQ(items[0].item, TopDownItem::kPerson);
    EXPECT_EQ(items[0].rgb, colours.body);
    EXPECT_EQ(items[0].outline, colours.outline);
  }
}

}  // namespace
}  // namespace pavilion::sim
