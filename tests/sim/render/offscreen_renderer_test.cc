// The off-screen renderer (sim/render/offscreen_renderer.h): silhouettes and
// edges where the pinhole model puts them, bit-identical pictures from any
// instance and thread, the world's parts in their colours at their places.
#include "sim/render/offscreen_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "sim/render/top_down_view.h"
#include "sim/world/world.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kCameraHeightM = 1.0;
constexpr double kWallX = 6.0;  // the backdrop wall's face towards the camera is at x = 5.9
// Grey levels: the dark pole and box against the light backdrop (lit, the
// backdrop is above 100 and the dark parts below 20); the threshold between.
constexpr int kDarkBelow = 60;
// Edges falling this close to a pixel centre are ties the rasterizer may
// resolve either way (its sub-pixel grid is 1/256 px).
constexpr double kTiePx = 0.02;

// 640 x 480 with a 60 deg horizontal field of view and the principal point
// off the centre (so that a sign error in c_u or c_v shows).
core::CameraIntrinsics Camera() {
  core::CameraIntrinsics c;
  c.width_px = 640;
  c.height_px = 480;
  c.focal_px = 320.0 / std::tan(kPi / 6);
  c.center_u_px = 311.3;
  c.center_v_px = 247.6;
  return c;
}

RenderView ViewFrom(const Eigen::Vector3d& position_m, double yaw_rad) {
  RenderView view;
  view.world_from_camera =
      Eigen::Translation3d(position_m) * Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ());
  view.intrinsics = Camera();
  return view;
}

// A floor, a light backdrop wall across x = kWallX and whatever the test adds.
WorldDescription Studio() {
  WorldDescription d;
  d.name = "studio";
  d.materials["floor"] = Material{0.8, 0.0, {0.45, 0.45, 0.45, 1}, core::LaserResponse::kNormal};
  d.materials["white"] = Material{0.8, 0.0, {0.95, 0.95, 0.95, 1}, core::LaserResponse::kNormal};
  d.materials["black"] = Material{0.8, 0.0, {0.05, 0.05, 0.05, 1}, core::LaserResponse::kNormal};
  d.materials["red"] = Material{0.8, 0.0, {0.8, 0.1, 0.1, 1}, core::LaserResponse::kNormal};
  d.materials["blue"] = Material{0.8, 0.0, {0.1, 0.2, 0.9, 1}, core::LaserResponse::kNormal};
  d.floor = {{-10, -10}, {10, 10}, "floor", {}};
  Wall w;
  w.id = "backdrop";
  w.points_m = {{kWallX, -10}, {kWallX, 10}};
  w.height_m = 3.0;
  w.material = "white";
  d.walls.push_back(w);
  return d;
}

int Grey(const core::GrayImage& image, int u, int v) { return image.at(u, v); }

std::array<std::uint8_t, 3> RgbAt(const core::RgbImage& image, int u, int v) {
  const std::size_t i = (static_cast<std::size_t>(v) * image.width + u) * 3;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

std::array<std::uint8_t, 3> Shaded(const WorldDescription& d, const std::string& material,
                                   const Eigen::Vector3d& normal) {
  const auto c = ShadedColour(d.MaterialNamed(material).rgba, normal);
  return {c[0], c[1], c[2]};
}

// The first and last dark pixel of row v, or {-1, -1}.
std::array<int, 2> DarkRun(const core::GrayImage& image, int v) {
  std::array<int, 2> run{-1, -1};
  for (int u = 0; u < image.width; ++u) {
    if (Grey(image, u, v) >= kDarkBelow) continue;
    if (run[0] < 0) run[0] = u;
    run[1] = u;
  }
  return run;
}

// The first pixel whose centre lies at or beyond coordinate x (a left or
// top edge), and whether x is too close to a centre to call.
int FirstCentreAfter(double x, bool* tie) {
  *tie = std::abs(x - 0.5 - std::round(x - 0.5)) < kTiePx;
  return static_cast<int>(std::ceil(x - 0.5));
}

// A thin dark pole 2 m from the camera at several bearings (both signs, up
// to 20 deg) against the backdrop: in the middle row the pole's first and
// last pixels are those whose centres the ideal silhouette covers, and its
// centre (first + last + 1) / 2 is the bearing's column within 0.5 px.
TEST(OffscreenRendererTest, PoleSilhouetteAtTheBearingsColumn) {
  constexpr double kRadiusM = 0.03, kRangeM = 2.0;
  OffscreenRenderer renderer;
  const Eigen::Vector3d eye(-1.0, 0.5, kCameraHeightM);
  const double yaw = 0.15;  // the camera turned and moved: the world pose is applied
  double max_error_px = 0.0;
  for (const double bearing_deg : {-20.0, -11.5, -3.0, 0.0, 4.7, 13.2, 20.0}) {
    const double bearing = bearing_deg * kPi / 180.0;
    WorldDescription d = Studio();
    Cylinder pole;
    pole.id = "pole";
    pole.position_m =
        eye.head<2>() + kRangeM * Eigen::Vector2d(std::cos(yaw + bearing), std::sin(yaw + bearing));
    pole.radius_m = kRadiusM;
    pole.height_m = 2.5;
    pole.material = "black";
    d.cylinders.push_back(pole);
    const World world(d, WorldOptions{});
    const RenderView view = ViewFrom(eye, yaw);
    const core::GrayImage image = renderer.RenderGray(world, view);
    const int row = 240;
    const std::array<int, 2> run = DarkRun(image, row);
    ASSERT_GE(run[0], 0) << bearing_deg;
    // The silhouette's tangents from the camera.
    const double half = std::asin(kRadiusM / kRangeM);
    const double left_u = core::ColumnOfBearing(view.intrinsics, bearing + half);
    const double right_u = core::ColumnOfBearing(view.intrinsics, bearing - half);
    bool tie_left = false, tie_right = false;
    const int first = FirstCentreAfter(left_u, &tie_left);
    const int last = FirstCentreAfter(right_u, &tie_right) - 1;
    if (!tie_left) {
      EXPECT_EQ(run[0], first) << bearing_deg << " left edge at u " << left_u;
    }
    if (!tie_right) {
      EXPECT_EQ(run[1], last) << bearing_deg << " right edge at u " << right_u;
    }
    const double centre = 0.5 * (run[0] + run[1] + 1);
    const double error = centre - core::ColumnOfBearing(view.intrinsics, bearing);
    EXPECT_LE(std::abs(error), 0.5) << bearing_deg;
    max_error_px = std::max(max_error_px, std::abs(error));
  }
  RecordProperty("max_centre_error_px", std::to_string(max_error_px));
}

// The top edge of a dark box face-on 3 m ahead (1 m deep), above and below
// the camera: every column through it turns dark at the first row whose
// centre lies below v = c_v - f dz / x (rows run top down), with the backdrop
// above.
TEST(OffscreenRendererTest, BoxTopEdgeAtItsRow) {
  OffscreenRenderer renderer;
  for (const double top_m : {1.4, 0.7}) {
    WorldDescription d = Studio();
    Box box;
    box.id = "box";
    box.pose = {3.5, 0.0, 0.0};
    box.size_m = {1.0, 2.0, top_m};
    box.material = "black";
    d.boxes.push_back(box);
    const World world(d, WorldOptions{});
    const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
    const core::GrayImage image = renderer.RenderGray(world, view);
    // Above the camera the near top edge shows, below it the far one.
    const double edge_x = top_m > kCameraHeightM ? 3.0 : 4.0;
    const double v_edge =
        view.intrinsics.center_v_px - view.intrinsics.focal_px * (top_m - kCameraHeightM) / edge_x;
    bool tie = false;
    const int first_dark = FirstCentreAfter(v_edge, &tie);
    ASSERT_FALSE(tie);
    for (const int u : {250, 311, 400}) {
      EXPECT_GE(Grey(image, u, first_dark - 1), kDarkBelow) << top_m << " u " << u;
      EXPECT_LT(Grey(image, u, first_dark), kDarkBelow) << top_m << " u " << u;
    }
  }
}

// A world with something of every kind: a wall corner, boxes, a cylinder, a
// door, a dynamic body, a robot and one visitor.
struct BusyScene {
  std::unique_ptr<World> world;
  int spawned = 0;  // visitors placed

  BusyScene() {
    WorldDescription d = Studio();
    d.materials["visitor"] = Material{};
    Wall corner;
    corner.id = "corner";
    corner.points_m = {{4, 3}, {3, 1.5}, {4.5, 0.8}};
    corner.material = "red";
    d.walls.push_back(corner);
    Box box;
    box.id = "crate";
    box.pose = {4.0, -1.5, 0.7};
    box.size_m = {0.8, 0.8, 1.2};
    box.material = "blue";
    d.boxes.push_back(box);
    Cylinder drum;
    drum.id = "drum";
    drum.position_m = {5.0, -0.3};
    drum.radius_m = 0.4;
    drum.height_m = 1.5;
    drum.material = "red";
    d.cylinders.push_back(drum);
    Door door;
    door.id = "door";
    door.hinge_m = {5.0, -4.0};
    door.closed_yaw_rad = kPi / 2;
    door.open_yaw_rad = kPi;
    door.material = "blue";
    d.doors.push_back(door);
    world = std::make_unique<World>(d, WorldOptions{});
    BodySpec body;
    body.id = "ball";
    body.shape.type = BodyShapeType::kSphere;
    body.shape.radius_m = 0.3;
    body.pose = {3.0, -0.6, 0.0};
    body.material = "red";
    world->AddBody(body);
    pavilion::testing::WorldRobot robot{"robot", pavilion::testing::PygmalionLikeModel("blue"),
                                        SystematicErrors{}, core::Pose2{2.5, 1.0, 0.5}};
    pavilion::testing::AddRobot(*world, robot);
    CrowdSpec crowd;
    crowd.material = "visitor";
    crowd.options.pool_size = 5;  // at least the largest group
    crowd.options.max_present = 1;
    crowd.options.watch_spots = 0;
    crowd.options.visit.group_fraction = 0.0;
    crowd.entrance = {{-3, -1}, {-2, -1}, {-2, 1}, {-3, 1}};
    crowd.exit = {{-9, 8}, {-8, 8}, {-8, 9}, {-9, 9}};  // this side of the backdrop
    crowd.attractions = {{"far", core::Pose2{-8.0, 8.0, 0.0}, 1.0}};
    world->AddCrowd(crowd, 1);
    spawned = world->mutable_crowd()->SpawnGroup({2.0, -1.2}, 1);
    for (int i = 0; i < 20; ++i) world->Step();
  }
};

// Repeated pictures, pictures of a second renderer and of renderers drawing
// concurrently on two threads are the same bytes.
TEST(OffscreenRendererTest, PicturesAreBitIdentical) {
  BusyScene scene;
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.1);
  OffscreenRenderer a;
  const core::RgbImage reference = a.RenderRgb(*scene.world, view);
  EXPECT_EQ(a.RenderRgb(*scene.world, view).pixels, reference.pixels);
  OffscreenRenderer b;
  EXPECT_EQ(b.RenderRgb(*scene.world, view).pixels, reference.pixels);
  constexpr int kFrames = 20;
  std::vector<int> mismatches(2, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      OffscreenRenderer own;
      for (int i = 0; i < kFrames; ++i) {
        if (own.RenderRgb(*scene.world, view).pixels != reference.pixels) ++mismatches[t];
      }
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(mismatches[0], 0);
  EXPECT_EQ(mismatches[1], 0);
  // One renderer handed from thread to thread.
  std::thread([&] { EXPECT_EQ(a.RenderRgb(*scene.world, view).pixels, reference.pixels); }).join();
}

// The grey picture is the RGB picture's rounded luminance.
TEST(OffscreenRendererTest, GreyIsTheLuminanceOfTheColours) {
  BusyScene scene;
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.1);
  OffscreenRenderer renderer;
  const core::RgbImage rgb = renderer.RenderRgb(*scene.world, view);
  const core::GrayImage grey = renderer.RenderGray(*scene.world, view);
  ASSERT_EQ(grey.width, rgb.width);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
    const double y =
        0.299 * rgb.pixels[3 * i] + 0.587 * rgb.pixels[3 * i + 1] + 0.114 * rgb.pixels[3 * i + 2];
    ASSERT_NEAR(grey.pixels[i], y, 0.5 + 1e-9) << i;
  }
}

// The backdrop fills the region between its projected bottom and top edges
// in its lit colour, the floor below it, the background above it.
TEST(OffscreenRendererTest, WallFillsItsRegionInItsColour) {
  const WorldDescription d = Studio();
  const World world(d, WorldOptions{});
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  OffscreenRenderer renderer;
  RenderScene scene;
  const core::RgbImage image = renderer.RenderRgb(world, view, scene);
  const core::CameraIntrinsics& c = view.intrinsics;
  const double face_x = kWallX - 0.1;
  const double v_top = c.center_v_px - c.focal_px * (3.0 - kCameraHeightM) / face_x;
  const double v_bottom = c.center_v_px - c.focal_px * (0.0 - kCameraHeightM) / face_x;
  const auto wall = Shaded(d, "white", {-1, 0, 0});
  const auto floor = Shaded(d, "floor", {0, 0, 1});
  const std::array<std::uint8_t, 3> sky = scene.background_rgb;
  for (int u = 0; u < c.width_px; u += 7) {
    for (int v = 0; v < c.height_px; v += 3) {
      const double centre = v + 0.5;
      if (std::abs(centre - v_top) < 1.0 || std::abs(centre - v_bottom) < 1.0) continue;
      const auto expected = centre < v_top ? sky : centre < v_bottom ? wall : floor;
      ASSERT_EQ(RgbAt(image, u, v), expected) << "u " << u << " v " << v;
    }
  }
}

// A robot appears in its chassis' colour where its chassis projects, and a
// picture with that robot hidden shows what stands behind it.
TEST(OffscreenRendererTest, RobotAppearsUnlessHidden) {
  const WorldDescription d = Studio();
  World world(d, WorldOptions{});
  pavilion::testing::WorldRobot spec{"robot", pavilion::testing::PygmalionLikeModel("black"),
                                     SystematicErrors{}, core::Pose2{3.0, 0.0, 0.0}};
  pavilion::testing::AddRobot(world, spec);
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  OffscreenRenderer renderer;
  const core::GrayImage seen = renderer.RenderGray(world, view);
  RenderScene hide;
  hide.hide_robot = 0;
  const core::GrayImage hidden = renderer.RenderGray(world, view, hide);
  // The chassis' front face at x = 3 - 0.225 spans z 0.04 .. 0.70: its middle.
  const core::CameraIntrinsics& c = view.intrinsics;
  const int u = static_cast<int>(c.center_u_px);
  const int v = static_cast<int>(c.center_v_px - c.focal_px * (0.37 - kCameraHeightM) / 2.775);
  EXPECT_LT(Grey(seen, u, v), kDarkBelow);
  EXPECT_GT(Grey(hidden, u, v), kDarkBelow);  // the floor behind it
  // Hidden, the picture is the empty studio's.
  const World empty(d, WorldOptions{});
  EXPECT_EQ(hidden.pixels, renderer.RenderGray(empty, view).pixels);
}

// A visitor of the crowd stands where the crowd put them, torso in their
// colours; doors are drawn in their current state.
TEST(OffscreenRendererTest, PeopleAndDoorsAtTheirState) {
  BusyScene scene;
  World& world = *scene.world;
  ASSERT_EQ(scene.spawned, 1);
  const auto& people = world.crowd()->people();
  const auto present = std::find_if(people.begin(), people.end(),
                                    [](const crowd::PersonState& p) { return p.present; });
  ASSERT_NE(present, people.end());
  const crowd::PersonState& person = *present;
  const Eigen::Vector3d eye(0, 0, kCameraHeightM);
  const RenderView view = ViewFrom(eye, 0.0);
  OffscreenRenderer renderer;
  const core::RgbImage image = renderer.RenderRgb(world, view);
  // The torso's centre line at 1.2 m (between hip and shoulders).
  const Eigen::Vector2d p = person.position_m;
  const core::CameraIntrinsics& c = view.intrinsics;
  const int u = static_cast<int>(std::floor(core::ColumnOfBearing(c, std::atan2(p.y(), p.x()))));
  const int v = static_cast<int>(std::floor(c.center_v_px - c.focal_px * 0.2 / p.x()));
  const PersonColours colours = PersonColours::From(kPersonRgb);
  std::set<std::array<std::uint8_t, 3>> torso;
  for (int k = 0; k < 720; ++k) {
    const double a = k * kPi / 360;
    const auto s = ShadedColour(
        {colours.body[0] / 255.0, colours.body[1] / 255.0, colours.body[2] / 255.0, 1.0},
        {std::cos(a), std::sin(a), 0.0});
    torso.insert({s[0], s[1], s[2]});
  }
  EXPECT_TRUE(torso.contains(RgbAt(image, u, v))) << "u " << u << " v " << v;

  // The door swings; the picture of the door's place changes and comes back.
  const RenderView door_view = ViewFrom(eye, std::atan2(-3.5, 5.0));
  const core::RgbImage closed = renderer.RenderRgb(world, door_view);
  world.SetDoorOpen("door", true);
  const core::RgbImage open = renderer.RenderRgb(world, door_view);
  EXPECT_NE(open.pixels, closed.pixels);
  world.SetDoorOpen("door", false);
  EXPECT_EQ(renderer.RenderRgb(world, door_view).pixels, closed.pixels);
}

// Two faces of a box turned 45 deg towards the camera meet at a vertical
// edge with a clear step in grey (flat shading by fixed lights).
TEST(OffscreenRendererTest, BoxCornerShowsContrast) {
  WorldDescription d = Studio();
  Box box;
  box.id = "box";
  box.pose = {3.0, 0.0, kPi / 4};
  box.size_m = {1.0, 1.0, 2.0};
  box.material = "white";
  d.boxes.push_back(box);
  const World world(d, WorldOptions{});
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  OffscreenRenderer renderer;
  const core::GrayImage image = renderer.RenderGray(world, view);
  const int u = static_cast<int>(core::ColumnOfBearing(view.intrinsics, 0.0));
  EXPECT_GE(std::abs(Grey(image, u - 10, 240) - Grey(image, u + 10, 240)), 20);
}

// A mesh element (Robox's lower base, an octagonal prism 0.68 m across flats
// from 3 cm to 0.40 m) stands where it is placed, in its material's colour
// (mesh files are drawn two-sided: either face's shade).
TEST(OffscreenRendererTest, MeshStandsWhereItIsPlaced) {
  WorldDescription d = Studio();
  Mesh mesh;
  mesh.id = "base";
  mesh.file = PAVILION_SOURCE_DIR "/robots/robox/meshes/base_lower.obj";
  mesh.position_m = {3.0, 0.0, 0.0};
  mesh.material = "blue";
  d.meshes.push_back(mesh);
  const World world(d, WorldOptions{});
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  OffscreenRenderer renderer;
  const core::RgbImage image = renderer.RenderRgb(world, view);
  const core::CameraIntrinsics& c = view.intrinsics;
  const int u = static_cast<int>(c.center_u_px);
  const auto row = [&](double z_m, double x_m) {
    return static_cast<int>(std::floor(c.center_v_px - c.focal_px * (z_m - kCameraHeightM) / x_m));
  };
  const auto front = RgbAt(image, u, row(0.2, 2.66));
  EXPECT_TRUE(front == Shaded(d, "blue", {-1, 0, 0}) || front == Shaded(d, "blue", {1, 0, 0}));
  // Above its top (0.40 m), the backdrop.
  EXPECT_EQ(RgbAt(image, u, row(0.5, kWallX - 0.1)), Shaded(d, "white", {-1, 0, 0}));
}

// Faces towards the four horizontal axes and up differ in brightness by at
// least 0.1 of full scale (FaceShade's contract), and every shade is in (0, 1].
TEST(OffscreenRendererTest, FacesOfDifferentDirectionsDifferInShade) {
  const std::vector<Eigen::Vector3d> normals{
      {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  for (std::size_t i = 0; i < normals.size(); ++i) {
    EXPECT_GT(FaceShade(normals[i]), 0.0);
    EXPECT_LE(FaceShade(normals[i]), 1.0);
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GE(std::abs(FaceShade(normals[i]) - FaceShade(normals[j])), 0.1) << i << " " << j;
    }
  }
}

// Each world has its own static geometry: a renderer that drew one world
// draws the next one (even at the same address) as that world.
TEST(OffscreenRendererTest, StaticGeometryFollowsTheWorld) {
  const RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  OffscreenRenderer renderer;
  WorldDescription with_box = Studio();
  Box box;
  box.id = "box";
  box.pose = {3.0, 0.0, 0.0};
  box.size_m = {1.0, 1.0, 2.0};
  box.material = "black";
  with_box.boxes.push_back(box);
  core::GrayImage plain, boxed;
  for (int round = 0; round < 2; ++round) {
    {
      auto world = std::make_unique<World>(Studio(), WorldOptions{});
      plain = renderer.RenderGray(*world, view);
    }
    {
      auto world = std::make_unique<World>(with_box, WorldOptions{});
      boxed = renderer.RenderGray(*world, view);
    }
    EXPECT_GE(Grey(plain, 311, 240), kDarkBelow);
    EXPECT_LT(Grey(boxed, 311, 240), kDarkBelow);
  }
}

// Bad views and a second llvmpipe thread count are refused.
TEST(OffscreenRendererTest, RefusesBadViewsAndLateThreadChanges) {
  const World world(Studio(), WorldOptions{});
  OffscreenRenderer renderer;
  RenderView view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  view.intrinsics.focal_px = 0.0;
  EXPECT_THROW(renderer.RenderGray(world, view), std::invalid_argument);
  view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  view.far_m = view.near_m;
  EXPECT_THROW(renderer.RenderGray(world, view), std::invalid_argument);
  EXPECT_THROW(ConfigureLlvmpipe(-1), std::invalid_argument);
  EXPECT_NO_THROW(ConfigureLlvmpipe(LlvmpipeThreads()));
  EXPECT_THROW(ConfigureLlvmpipe(LlvmpipeThreads() + 1), std::logic_error);
  // Another size on the same renderer.
  view = ViewFrom({0, 0, kCameraHeightM}, 0.0);
  view.intrinsics.width_px = 64;
  view.intrinsics.height_px = 48;
  const core::GrayImage small = renderer.RenderGray(world, view);
  EXPECT_EQ(small.width, 64);
  EXPECT_EQ(small.pixels.size(), 64u * 48u);
}

// A camera on a robot's mount: base pose then the link's z, yaw, pitch, roll.
TEST(OffscreenRendererTest, WorldFromMountComposesBaseAndLink) {
  MountSpec mount;
  mount.pose = {0.2, -0.1, 0.0};
  mount.z_m = 1.5;
  mount.pitch_rad = -kPi / 2;  // looking straight up
  const Eigen::Isometry3d pose = WorldFromMount({1.0, 2.0, kPi / 2}, mount);
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(1.1, 2.2, 1.5), 1e-12));
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

}  // namespace
}  // namespace pavilion::sim
