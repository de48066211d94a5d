// Reading differential-drive robots from URDF: the shipped models against the
// thesis' figures, and one malformed file per error class.
#include "sim/robot/urdf_robot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "core/geometry/polygon.h"
#include "tests/support/test_files.h"

namespace pavilion::sim {
namespace {

using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

constexpr double kPi = std::numbers::pi;

UrdfDriveNames ShippedNames() {
  UrdfDriveNames names;
  names.caster_links = {"caster_front", "caster_rear"};
  return names;
}

RobotDescription LoadShipped(const std::string& robot) {
  return LoadUrdfRobot(std::string(PAVILION_SOURCE_DIR) + "/robots/" + robot + "/robot.urdf",
                       ShippedNames());
}

// A small valid robot: 0.4 m box chassis, wheels r = 0.1 m at y = ±0.2, one caster.
const std::string kUrdf = R"(<?xml version="1.0"?>
<robot name="tiny">
  <link name="base_link"/>
  <joint name="chassis_joint" type="fixed">
    <parent link="base_link"/>
    <child link="chassis"/>
  </joint>
  <link name="chassis">
    <inertial>
      <origin xyz="0 0 0.3"/>
      <mass value="20"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>
    </inertial>
    <collision>
      <origin xyz="0 0 0.3"/>
      <geometry><box size="0.4 0.4 0.5"/></geometry>
    </collision>
  </link>
  <joint name="left_wheel_joint" type="continuous">
    <parent link="chassis"/>
    <child link="left_wheel"/>
    <origin xyz="0 0.2 0.1"/>
    <axis xyz="0 1 0"/>
  </joint>
  <link name="left_wheel">
    <inertial>
      <mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <collision>
      <origin rpy="1.5707963267948966 0 0"/>
      <geometry><cylinder radius="0.1" length="0.03"/></geometry>
    </collision>
  </link>
  <joint name="right_wheel_joint" type="continuous">
    <parent link="chassis"/>
    <child link="right_wheel"/>
    <origin xyz="0 -0.2 0.1"/>
    <axis xyz="0 1 0"/>
  </joint>
  <link name="right_wheel">
    <inertial>
      <mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
    <collision>
      <origin rpy="1.5707963267948966 0 0"/>
      <geometry><cylinder radius="0.1" length="0.03"/></geometry>
    </collision>
  </link>
  <joint name="caster_joint" type="fixed">
    <parent link="chassis"/>
    <child link="caster"/>
    <origin xyz="0.15 0 0.02"/>
  </joint>
  <link name="caster">
    <collision><geometry><sphere radius="0.02"/></geometry></collision>
  </link>
  <joint name="laser_joint" type="fixed">
    <parent link="chassis"/>
    <child link="laser"/>
    <origin xyz="0.1 0 0.5" rpy="0 0 0.5"/>
  </joint>
  <link name="laser"/>
</robot>
)";

UrdfDriveNames TinyNames() {
  UrdfDriveNames names;
  names.caster_links = {"caster"};
  return names;
}

// kUrdf with `from` (which must occur) replaced by `to`.
std::string Edited(const std::string& from, const std::string& to) {
  std::string text = kUrdf;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the test URDF";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Loads `text` written as robot.urdf; returns the error after checking that it
// names the file and, when `marker` is set, the line holding it.
UrdfError ExpectError(const std::string& text, const std::string& marker,
                      const UrdfDriveNames& names = TinyNames()) {
  const std::string path = WriteFile(TestDir(), "robot.urdf", text);
  try {
    LoadUrdfRobot(path, names);
  } catch (const UrdfError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(Contains(what, path + ":"));
    if (!marker.empty()) {
      EXPECT_TRUE(Contains(what, path + ":" + std::to_string(LineOf(text, marker)) + ": "));
    }
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    return e;
  }
  ADD_FAILURE() << "LoadUrdfRobot accepted the file";
  return UrdfError("");
}

// Confirms that the tiny robot reads with the poses, sizes and masses written.
TEST(UrdfRobotTest, ReadsWheelsCastersMountsAndMass) {
  const std::string path = WriteFile(TestDir(), "robot.urdf", kUrdf);
  const RobotDescription d = LoadUrdfRobot(path, TinyNames());
  EXPECT_EQ(d.model, "tiny");
  EXPECT_EQ(d.urdf_file, path);
  EXPECT_EQ(d.left_wheel.joint, "left_wheel_joint");
  EXPECT_DOUBLE_EQ(d.left_wheel.radius_m, 0.1);
  EXPECT_DOUBLE_EQ(d.left_wheel.width_m, 0.03);
  EXPECT_DOUBLE_EQ(d.left_wheel.mass_kg, 1.0);
  EXPECT_NEAR(d.left_wheel.position_m.y(), 0.2, 1e-12);
  EXPECT_NEAR(d.right_wheel.position_m.y(), -0.2, 1e-12);
  EXPECT_NEAR(d.wheelbase_m(), 0.4, 1e-12);
  ASSERT_EQ(d.casters.size(), 1u);
  EXPECT_NEAR(d.casters[0].position_m.x(), 0.15, 1e-12);
  EXPECT_DOUBLE_EQ(d.casters[0].radius_m, 0.02);
  EXPECT_DOUBLE_EQ(d.chassis_mass_kg, 20.0);
  EXPECT_DOUBLE_EQ(d.total_mass_kg(), 22.0);
  EXPECT_NEAR(d.chassis_com_m.z(), 0.3, 1e-12);
  const MountSpec& laser = d.Mount("laser");
  EXPECT_NEAR(laser.pose.x_m, 0.1, 1e-12);
  EXPECT_NEAR(laser.pose.theta_rad, 0.5, 1e-12);
  EXPECT_NEAR(laser.z_m, 0.5, 1e-12);
  EXPECT_NO_THROW(d.Mount("base_link"));
  EXPECT_NO_THROW(d.Mount("chassis"));
  EXPECT_THROW(d.Mount("left_wheel"), std::out_of_range);  // wheels are not mounts
  // Footprint: the box seen from above, counter-clockwise; height range of the box.
  ASSERT_EQ(d.footprint_m.size(), 4u);
  EXPECT_NEAR(core::SignedArea(d.footprint_m), 0.16, 1e-12);
  EXPECT_NEAR(d.chassis_base_z_m, 0.05, 1e-12);
  EXPECT_NEAR(d.chassis_height_m, 0.5, 1e-12);
  ASSERT_EQ(d.chassis_shapes.size(), 1u);  // the caster's sphere is not a chassis shape
  EXPECT_EQ(d.chassis_shapes[0].type, CollisionShape::Type::kBox);
}

// Confirms Robox matches the thesis: 115 kg (§6.5), 1.65 m tall and octagonal
// (A.5), two back-to-back scanners and markers at its sides (§6.3.5.1).
TEST(UrdfRobotTest, RoboxMatchesTheThesis) {
  const RobotDescription d = LoadShipped("robox");
  EXPECT_NEAR(d.total_mass_kg(), 115.0, 1e-9);
  EXPECT_NEAR(d.chassis_base_z_m + d.chassis_height_m, 1.65, 1e-9);
  ASSERT_EQ(d.footprint_m.size(), 8u);  // the octagon of meshes/base_lower.obj
  EXPECT_GT(core::SignedArea(d.footprint_m), 0.0);
  for (const Eigen::Vector2d& p : d.footprint_m) {
    EXPECT_NEAR(p.norm(), 0.34 / std::cos(kPi / 8), 1e-5);  // regular, 0.68 m across flats
  }
  EXPECT_NEAR(d.left_wheel.position_m.y(), -d.right_wheel.position_m.y(), 1e-12);
  EXPECT_EQ(d.casters.size(), 2u);
  const MountSpec& front = d.Mount("laser_front");
  const MountSpec& rear = d.Mount("laser_rear");
  EXPECT_NEAR(front.pose.theta_rad, 0.0, 1e-9);
  EXPECT_NEAR(std::abs(rear.pose.theta_rad), kPi, 1e-9);  // back to back
  EXPECT_NEAR(front.z_m, rear.z_m, 1e-12);
  EXPECT_NEAR(d.Mount("camera_up").pitch_rad, -kPi / 2, 1e-9);  // looks at the ceiling
  EXPECT_NO_THROW(d.Mount("camera_forward"));
  EXPECT_NEAR(std::abs(d.Mount("marker_left").pose.y_m), 0.34, 1e-12);
  EXPECT_NEAR(std::abs(d.Mount("marker_right").pose.y_m), 0.34, 1e-12);
  // The chassis inertia is a proper inertia: symmetric, positive definite.
  EXPECT_TRUE(d.chassis_inertia_kgm2.isApprox(d.chassis_inertia_kgm2.transpose()));
  EXPECT_GT(d.chassis_inertia_kgm2.determinant(), 0.0);
  EXPECT_TRUE(core::Contains(d.footprint_m, d.chassis_com_m.head<2>()));
}

// Confirms the chassis is stacked in slabs where its collision shapes begin and
// end: Robox's base recessed to a 0.48 m octagon at scanner height (0.40–0.60 m,
// §6.3.5.1), the 0.68 m octagon below and above, then the column and the face;
// the footprint stays the 0.68 m octagon, and the simulator builds these slabs.
TEST(UrdfRobotTest, RoboxIsRecessedAtScannerHeight) {
  const RobotDescription d = LoadShipped("robox");
  struct Slab {
    double z0, z1, apothem;  // apothem: half the width across flats (m)
  };
  const Slab expected[] = {{0.03, 0.40, 0.34}, {0.40, 0.60, 0.24}, {0.60, 0.75, 0.34}};
  ASSERT_EQ(d.chassis_prisms.size(), 5u);  // three base slabs, the column, the face
  for (int k = 0; k < 3; ++k) {
    const ChassisPrism& p = d.chassis_prisms[k];
    // The mesh loader reads single-precision vertices.
    EXPECT_NEAR(p.z0_m, expected[k].z0, 1e-7) << k;
    EXPECT_NEAR(p.z1_m, expected[k].z1, 1e-7) << k;
    ASSERT_EQ(p.outline_m.size(), 8u) << k;
    for (const Eigen::Vector2d& v : p.outline_m) {
      EXPECT_NEAR(v.norm(), expected[k].apothem / std::cos(kPi / 8), 1e-6) << k;
    }
  }
  EXPECT_NEAR(d.chassis_prisms[3].z1_m, 1.45, 1e-9);  // the column
  EXPECT_NEAR(d.chassis_prisms[4].z1_m, 1.65, 1e-9);  // the face
  EXPECT_EQ(d.ChassisPrisms().size(), 5u);            // footprint = hull of the slabs
  // A footprint given in place of the derived one makes the chassis its prism.
  RobotDescription given = d;
  given.footprint_m = {{-0.4, -0.4}, {0.4, -0.4}, {0.4, 0.4}, {-0.4, 0.4}};
  ASSERT_EQ(given.ChassisPrisms().size(), 1u);
  EXPECT_EQ(given.ChassisPrisms()[0].outline_m, given.footprint_m);
}

// Confirms Pygmalion matches appendix A.1: about 45 × 45 × 70 cm and 55 kg.
TEST(UrdfRobotTest, PygmalionMatchesTheThesis) {
  const RobotDescription d = LoadShipped("pygmalion");
  EXPECT_NEAR(d.total_mass_kg(), 55.0, 1e-9);
  EXPECT_NEAR(d.chassis_base_z_m + d.chassis_height_m, 0.70, 1e-9);
  ASSERT_EQ(d.footprint_m.size(), 4u);
  EXPECT_NEAR(core::SignedArea(d.footprint_m), 0.45 * 0.45, 1e-9);
  EXPECT_NEAR(std::abs(d.Mount("laser_rear").pose.theta_rad), kPi, 1e-9);
  EXPECT_NO_THROW(d.Mount("camera_forward"));
}

// Confirms that XML that does not parse is reported with its line.
TEST(UrdfRobotTest, MalformedXmlNamesTheLine) {
  const UrdfError e =
      ExpectError(Edited("  <link name=\"laser\"/>\n", "  <link name=\"laser\">\n"), "");
  EXPECT_TRUE(Contains(e.what(), "malformed XML"));
}

// Confirms that what urdfdom rejects is reported with urdfdom's reason, not printed.
TEST(UrdfRobotTest, UrdfdomRejectionIsReported) {
  const UrdfError e = ExpectError(
      Edited("  <link name=\"laser\"/>\n", "  <link name=\"laser\"/>\n  <link name=\"laser\"/>\n"),
      "");
  EXPECT_TRUE(Contains(e.what(), "not a valid URDF: link 'laser' is not unique"));
}

// Confirms that a file that is not there is reported, not crashed on.
TEST(UrdfRobotTest, MissingFileIsReported) {
  const std::string path = (TestDir() / "absent.urdf").string();
  try {
    LoadUrdfRobot(path, TinyNames());
    ADD_FAILURE() << "accepted a missing file";
  } catch (const UrdfError& e) {
    EXPECT_TRUE(Contains(e.what(), path + ": cannot open file"));
  }
}

// Confirms that a joint naming a link that does not exist names joint, link and line.
TEST(UrdfRobotTest, JointToMissingLinkIsReported) {
  const std::string text = Edited("<child link=\"laser\"/>", "<child link=\"lazer\"/>");
  const UrdfError e = ExpectError(text, "<joint name=\"laser_joint\"");
  EXPECT_TRUE(Contains(e.what(), "joint 'laser_joint': child link 'lazer' does not exist"));
}

// Confirms that a wheel joint without <axis> is caught although urdfdom
// silently defaults it to (1, 0, 0).
TEST(UrdfRobotTest, WheelJointWithoutAxisIsReported) {
  const std::string text = Edited("    <origin xyz=\"0 0.2 0.1\"/>\n    <axis xyz=\"0 1 0\"/>\n",
                                  "    <origin xyz=\"0 0.2 0.1\"/>\n");
  const UrdfError e = ExpectError(text, "<joint name=\"left_wheel_joint\"");
  EXPECT_TRUE(Contains(e.what(), "joint 'left_wheel_joint': continuous joint has no <axis>"));
}

// Confirms that a wheel axis not along +y of the base is reported.
TEST(UrdfRobotTest, WheelAxisMustBeAlongY) {
  const std::string text = Edited("    <origin xyz=\"0 -0.2 0.1\"/>\n    <axis xyz=\"0 1 0\"/>",
                                  "    <origin xyz=\"0 -0.2 0.1\"/>\n    <axis xyz=\"1 0 0\"/>");
  const UrdfError e = ExpectError(text, "<joint name=\"right_wheel_joint\"");
  EXPECT_TRUE(Contains(e.what(), "joint 'right_wheel_joint': axis must be along +y"));
}

// Confirms that a chassis of zero (or negative) mass is rejected by name.
TEST(UrdfRobotTest, ZeroMassChassisIsReported) {
  const UrdfError e =
      ExpectError(Edited("<mass value=\"20\"/>", "<mass value=\"0\"/>"), "<link name=\"chassis\"");
  EXPECT_TRUE(Contains(e.what(), "link 'chassis': the chassis needs an <inertial> with mass > 0"));
  const UrdfError n =
      ExpectError(Edited("<mass value=\"20\"/>", "<mass value=\"-3\"/>"), "<link name=\"chassis\"");
  EXPECT_TRUE(Contains(n.what(), "link 'chassis': mass must be"));
}

// Confirms that a wheel with no collision geometry is reported (no radius to read).
TEST(UrdfRobotTest, WheelWithoutCollisionIsReported) {
  const std::string text = Edited(R"(    <collision>
      <origin rpy="1.5707963267948966 0 0"/>
      <geometry><cylinder radius="0.1" length="0.03"/></geometry>
    </collision>
  </link>
  <joint name="right_wheel_joint")",
                                  R"(  </link>
  <joint name="right_wheel_joint")");
  const UrdfError e = ExpectError(text, "<link name=\"left_wheel\"");
  EXPECT_TRUE(Contains(e.what(), "link 'left_wheel': wheel has no collision geometry"));
}

// Confirms that wheels not symmetric about x (base not midway) are an error.
TEST(UrdfRobotTest, AsymmetricWheelsAreReported) {
  const UrdfError e =
      ExpectError(Edited("<origin xyz=\"0 -0.2 0.1\"/>", "<origin xyz=\"0 -0.25 0.1\"/>"),
                  "<joint name=\"left_wheel_joint\"");
  EXPECT_TRUE(Contains(e.what(), "not symmetric"));
}

// Confirms that an axle height different from the wheel radius (base not on the floor) is an error.
TEST(UrdfRobotTest, AxleMustBeAtWheelRadius) {
  const UrdfError e =
      ExpectError(Edited("<origin xyz=\"0 0.2 0.1\"/>", "<origin xyz=\"0 0.2 0.15\"/>"),
                  "<joint name=\"left_wheel_joint\"");
  EXPECT_TRUE(Contains(e.what(), "axle height"));
}

// Confirms that names that do not resolve say which one, for the caller to point at.
TEST(UrdfRobotTest, UnresolvedNamesSayWhichOne) {
  UrdfDriveNames names = TinyNames();
  names.chassis_link = "body";
  UrdfError e = ExpectError(kUrdf, "", names);
  EXPECT_EQ(e.unresolved_name(), UrdfError::Name::kChassisLink);
  EXPECT_TRUE(Contains(e.what(), "chassis link 'body' does not exist"));

  names = TinyNames();
  names.right_wheel_joint = "right_joint";
  e = ExpectError(kUrdf, "", names);
  EXPECT_EQ(e.unresolved_name(), UrdfError::Name::kRightWheelJoint);

  names = TinyNames();
  names.caster_links = {"caster", "caster_2"};
  e = ExpectError(kUrdf, "", names);
  EXPECT_EQ(e.unresolved_name(), UrdfError::Name::kCasterLink);
  EXPECT_EQ(e.caster_index(), 1);

  names = TinyNames();
  names.caster_links = {"laser"};  // exists, but has no sphere: a URDF problem
  e = ExpectError(kUrdf, "<link name=\"laser\"", names);
  EXPECT_EQ(e.unresolved_name(), UrdfError::Name::kNone);
  EXPECT_TRUE(Contains(e.what(), "a caster needs exactly one <collision>, a sphere"));
}

// Confirms that the base link must be the URDF's root.
TEST(UrdfRobotTest, BaseLinkMustBeTheRoot) {
  UrdfDriveNames names = TinyNames();
  names.base_link = "chassis";
  const UrdfError e = ExpectError(kUrdf, "<link name=\"chassis\"", names);
  EXPECT_EQ(e.unresolved_name(), UrdfError::Name::kBaseLink);
  EXPECT_TRUE(Contains(e.what(), "must be the root"));
}

// Confirms that a moving joint other than the two wheels is rejected.
TEST(UrdfRobotTest, OnlyWheelJointsMayMove) {
  const std::string text =
      Edited("<joint name=\"laser_joint\" type=\"fixed\">",
             "<joint name=\"laser_joint\" type=\"continuous\"><axis xyz=\"0 0 1\"/>");
  const UrdfError e = ExpectError(text, "<joint name=\"laser_joint\"");
  EXPECT_TRUE(Contains(e.what(), "joint 'laser_joint': only the two drive wheel joints may move"));
}

// Confirms that a mesh file that does not exist is reported with its link.
TEST(UrdfRobotTest, MissingMeshIsReported) {
  const UrdfError e =
      ExpectError(Edited("<box size=\"0.4 0.4 0.5\"/>", "<mesh filename=\"meshes/none.obj\"/>"),
                  "<link name=\"chassis\"");
  EXPECT_TRUE(Contains(e.what(), "link 'chassis': mesh file not found"));
}

// Confirms that a caster whose sphere does not touch the floor is an error.
TEST(UrdfRobotTest, CasterMustTouchTheFloor) {
  const UrdfError e =
      ExpectError(Edited("<origin xyz=\"0.15 0 0.02\"/>", "<origin xyz=\"0.15 0 0.05\"/>"),
                  "<link name=\"caster\"");
  EXPECT_TRUE(Contains(e.what(), "touch the floor"));
}

}  // namespace
}  // namespace pavilion::sim
