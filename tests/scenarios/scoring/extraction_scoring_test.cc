// Scoring of extracted lines against simulation ground truth (metrics.md,
// "Feature extraction"), and the acceptance of issue 5 on simulated SICK LMS 200
// scans in office_floor and expo_hall with noise on and visitors present.
#include "scenarios/scoring/extraction_scoring.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "core/features/line_extraction.h"
#include "core/random/random_stream.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {
namespace {

constexpr double kBeamHeightM = 0.5;
constexpr double kDeg = std::numbers::pi / 180.0;

// --- Synthetic cases -------------------------------------------------------

// A noise-free scan of a single wall x = 3 (face towards the sensor at the
// origin), readings every 0.5 deg over +-60 deg.
struct WallScan {
  core::LaserScan scan;
  core::LaserScanTruth truth;
  core::PlanarSection section;
};

// With a door of half-width half_door_m (> 0) the wall is two faces.
WallScan OneWall(double wall_x_m, double half_width_m, double half_door_m = 0.0) {
  WallScan w;
  const int element = w.section.AddElement({"wall", core::LaserResponse::kNormal, false, -1});
  // Solid on the left of a -> b: the solid lies at x > wall_x, so go down.
  if (half_door_m > 0.0) {
    w.section.segments.push_back(
        {Eigen::Vector2d(wall_x_m, half_width_m), Eigen::Vector2d(wall_x_m, half_door_m), element});
    w.section.segments.push_back({Eigen::Vector2d(wall_x_m, -half_door_m),
                                  Eigen::Vector2d(wall_x_m, -half_width_m), element});
  } else {
    w.section.segments.push_back({Eigen::Vector2d(wall_x_m, half_width_m),
                                  Eigen::Vector2d(wall_x_m, -half_width_m), element});
  }
  w.scan.max_range_m = 8.0;
  for (int i = 0; i <= 240; ++i) {
    const double b = (-60.0 + 0.5 * i) * kDeg;
    core::LaserReading reading;
    const double y = wall_x_m * std::tan(b);
    const bool hit = std::abs(y) <= half_width_m && std::abs(y) >= half_door_m;
    reading.bearing_rad = b;
    reading.valid = hit;
    reading.range_m = hit ? wall_x_m / std::cos(b) : 8.0;
    w.scan.readings.push_back(reading);
    w.truth.world_from_sensor.push_back({});
    w.truth.true_range_m.push_back(reading.range_m);
    w.truth.element.push_back(hit ? element : -1);
  }
  return w;
}

core::Segment SegmentOn(double alpha_rad, double r_m, double first_bearing_rad,
                        double last_bearing_rad) {
  core::Line line;
  line.alpha_rad = alpha_rad;
  line.r_m = r_m;
  line.covariance << 1e-5, 0.0, 0.0, 1e-4;  // sigma_alpha 0.18 deg, sigma_r 1 cm
  return core::MakeSegment(line, first_bearing_rad, last_bearing_rad, 0.0, 20, 0, 19);
}

TEST(ExtractionScoringTest, MatchesAWallAndRejectsWrongLines) {
  const WallScan w = OneWall(3.0, 2.0);
  const std::vector<core::Segment> segments = {
      SegmentOn(0.2 * kDeg, 3.01, -30 * kDeg, 30 * kDeg),  // good, inside the gate
      SegmentOn(0.0, 3.04, -10 * kDeg, 10 * kDeg),         // within 5 cm, outside the gate
      SegmentOn(3.0 * kDeg, 3.0, -10 * kDeg, 10 * kDeg),   // alpha off by 3 deg
      SegmentOn(0.0, 3.0, 40 * kDeg, 55 * kDeg),           // beyond the wall's end
  };
  const ExtractionScore score = ScoreExtraction(w.scan, w.truth, w.section, segments);
  ASSERT_EQ(score.walls.size(), 1u);
  EXPECT_TRUE(score.walls[0].in_view);
  EXPECT_NEAR(score.walls[0].line.alpha_rad, 0.0, 1e-12);
  EXPECT_NEAR(score.walls[0].line.r_m, 3.0, 1e-12);
  EXPECT_GT(score.walls[0].visible_length_m, 3.9);
  EXPECT_EQ(score.walls_in_view, 1);
  EXPECT_EQ(score.walls_found, 1);
  EXPECT_EQ(score.extracted, 4);
  EXPECT_EQ(score.false_positives, 2);
  EXPECT_EQ(score.wall_of_segment, (std::vector<int>{0, 0, -1, -1}));
  ASSERT_EQ(score.matches.size(), 2u);
  EXPECT_TRUE(score.matches[0].in_gate);  // (0.2 deg, 1 cm): d^2 = 1.22 + 1
  EXPECT_NEAR(score.matches[0].mahalanobis2, std::pow(0.2 * kDeg, 2) / 1e-5 + 1.0, 1e-9);
  EXPECT_FALSE(score.matches[1].in_gate);  // d^2 = 16

  ExtractionScoreAccumulator acc;
  acc.Add(score);
  acc.Add(score);
  const ExtractionFigures f = acc.Figures();
  EXPECT_EQ(f.scans, 2);
  EXPECT_DOUBLE_EQ(f.true_positive_rate, 1.0);
  EXPECT_DOUBLE_EQ(f.false_positive_rate, 0.5);
  EXPECT_DOUBLE_EQ(f.in_gate_fraction, 0.5);
  EXPECT_NEAR(f.mean_delta_r_m, 0.025, 1e-12);
  EXPECT_NEAR(f.sigma_delta_r_m, std::sqrt(4 * 0.015 * 0.015 / 3.0), 1e-12);
}

// A wall seen over less than 1 m, or only beyond 6 m, is not in view; a line on
// it is still no false positive.
TEST(ExtractionScoringTest, ShortAndDistantWallsAreNotInView) {
  const WallScan short_wall = OneWall(3.0, 0.45);
  const WallScan far_wall = OneWall(6.5, 3.0);
  const std::vector<core::Segment> on_short = {SegmentOn(0.0, 3.0, -8 * kDeg, 8 * kDeg)};
  const ExtractionScore a =
      ScoreExtraction(short_wall.scan, short_wall.truth, short_wall.section, on_short);
  ASSERT_EQ(a.walls.size(), 1u);
  EXPECT_FALSE(a.walls[0].in_view);
  EXPECT_EQ(a.walls_in_view, 0);
  EXPECT_EQ(a.false_positives, 0);
  const ExtractionScore b =
      ScoreExtraction(far_wall.scan, far_wall.truth, far_wall.section, on_short);
  ASSERT_EQ(b.walls.size(), 1u);
  EXPECT_FALSE(b.walls[0].in_view);  // seen from 6.5 m on: nothing within 6 m
  EXPECT_GT(b.walls[0].visible_length_m, 5.0);
  EXPECT_EQ(b.false_positives, 1);  // r off by 3.5 m
}

// A wall with a 1 m door is two walls on one line; a segment fused across the
// door matches the line and finds both; a segment on one piece finds that one.
TEST(ExtractionScoringTest, SegmentAcrossADoorFindsBothPieces) {
  const WallScan w = OneWall(3.0, 2.5, 0.5);
  const ExtractionScore both =
      ScoreExtraction(w.scan, w.truth, w.section, {SegmentOn(0.0, 3.0, -38 * kDeg, 38 * kDeg)});
  ASSERT_EQ(both.walls.size(), 2u);
  EXPECT_EQ(both.walls_in_view, 2);
  EXPECT_EQ(both.walls_found, 2);
  EXPECT_EQ(both.false_positives, 0);
  const ExtractionScore one =
      ScoreExtraction(w.scan, w.truth, w.section, {SegmentOn(0.0, 3.0, 10 * kDeg, 38 * kDeg)});
  EXPECT_EQ(one.walls_found, 1);
  EXPECT_EQ(one.false_positives, 0);
}

TEST(ExtractionScoringTest, ValidatesInput) {
  WallScan w = OneWall(3.0, 2.0);
  w.truth.element.pop_back();
  EXPECT_THROW(ScoreExtraction(w.scan, w.truth, w.section, {}), std::invalid_argument);
  ExtractionScoringOptions options;
  options.max_r_error_m = 0.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

// --- Simulated scans in the shipped worlds ---------------------------------

// Free sensor positions on a grid: clear of every primitive of the section at
// beam height by `clearance_m`, not inside an element's outline, and inside the
// building (rays in 16 directions all hit something).
std::vector<Eigen::Vector2d> FreeCells(const sim::World& world, const sim::WorldDescription& d,
                                       double spacing_m, double clearance_m) {
  const core::PlanarSection section = world.SectionAt(kBeamHeightM);
  std::vector<Eigen::Vector2d> cells;
  for (double y = d.floor.min_m.y() + 0.5; y < d.floor.max_m.y() - 0.5; y += spacing_m) {
    for (double x = d.floor.min_m.x() + 0.5; x < d.floor.max_m.x() - 0.5; x += spacing_m) {
      const Eigen::Vector2d p(x, y);
      bool ok = true;
      std::vector<double> winding(section.elements.size(), 0.0);
      for (const core::SectionSegment& s : section.segments) {
        const Eigen::Vector2d ab = s.b_m - s.a_m;
        const double t = std::clamp((p - s.a_m).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        if ((s.a_m + t * ab - p).norm() < clearance_m) ok = false;
        const Eigen::Vector2d u = s.a_m - p, v = s.b_m - p;
        winding[s.element] += std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
      }
      for (double w : winding) ok = ok && std::abs(w) < std::numbers::pi;
      for (const core::SectionCircle& c : section.circles) {
        if ((c.center_m - p).norm() < c.radius_m + clearance_m) ok = false;
      }
      for (int k = 0; k < 16 && ok; ++k) {
        const double a = k * std::numbers::pi / 8.0;
        const Eigen::Vector3d from(x, y, kBeamHeightM);
        const Eigen::Vector3d to = from + 200.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        ok = world.CastRay(from, to, -1, true).hit;
      }
      if (ok) cells.push_back(p);
    }
  }
  return cells;
}

void Print(const std::string& what, const ExtractionFigures& f) {
  std::printf(
      "[ info ] %s: %d scans; walls in view %d, found %d: TP rate %.4f (modelled surfaces %d / "
      "%d: %.4f); extracted %d, false "
      "positives %d: FP rate %.4f; matches %d: sigma dr %.2f mm (mean %.2f), sigma da %.3f deg "
      "(mean %.3f), in 95%% gate %.4f\n",
      what.c_str(), f.scans, f.walls_in_view, f.walls_found, f.true_positive_rate,
      f.modelled_walls_found, f.modelled_walls_in_view, f.modelled_true_positive_rate, f.extracted,
      f.false_positives, f.false_positive_rate, f.matches, 1e3 * f.sigma_delta_r_m,
      1e3 * f.mean_delta_r_m, f.sigma_delta_alpha_rad / kDeg, f.mean_delta_alpha_rad / kDeg,
      f.in_gate_fraction);
}

// `scans` sensor poses per noise seed, seeds first_seed .. first_seed +
// seed_count - 1, pooled.
ExtractionFigures ScoreWorld(
    const std::string& name, int visitors, int scans,
    const core::LineExtractionOptions& extraction = core::LineExtractionOptions::SickLms200(),
    std::uint64_t first_seed = 5, int seed_count = 3) {
  const sim::WorldDescription d = LoadWorldFile(ResolveWorldPath(name));
  sim::World world(d, sim::WorldOptions{});
  // Visitors (pedestrian-sized cylinders) on every k-th free cell.
  const std::vector<Eigen::Vector2d> visitor_cells = FreeCells(world, d, 1.3, 0.4);
  EXPECT_GE(static_cast<int>(visitor_cells.size()), visitors) << name;
  const std::size_t stride = std::max<std::size_t>(1, visitor_cells.size() / visitors);
  for (int v = 0; v < visitors && v * stride < visitor_cells.size(); ++v) {
    const Eigen::Vector2d& c = visitor_cells[v * stride];
    sim::BodySpec spec;
    spec.id = "visitor_" + std::to_string(v);
    spec.shape.type = sim::BodyShapeType::kCylinder;
    spec.shape.radius_m = 0.22;
    spec.shape.height_m = 1.7;
    spec.mass_kg = 70.0;
    spec.pose = {c.x(), c.y(), 0.0};
    spec.material = d.floor.material;
    world.AddBody(spec);
  }
  // Sensor poses among the visitors.
  const std::vector<Eigen::Vector2d> cells = FreeCells(world, d, 0.7, 0.5);
  EXPECT_GE(static_cast<int>(cells.size()), scans) << name;
  const core::PlanarSection section = world.SectionAt(kBeamHeightM);
  ExtractionScoreAccumulator acc;
  // Three noise seeds; headings differ per seed, positions repeat.
  for (std::uint64_t seed = first_seed; seed < first_seed + seed_count; ++seed) {
    sim::LaserScanner laser("laser", sim::LaserScannerOptions::Profile("sick_lms200"),
                            core::Pose2{}, kBeamHeightM, core::RandomStream(seed, 1));
    EXPECT_TRUE(laser.options().noise);
    EXPECT_TRUE(laser.options().effects);
    const double step = static_cast<double>(cells.size()) / scans;
    for (int k = 0; k < scans; ++k) {
      const Eigen::Vector2d& c = cells[static_cast<std::size_t>(k * step)];
      const double heading = 2.399963229728653 * (k + 1000.0 * static_cast<double>(seed));
      const core::Pose2 pose{c.x(), c.y(), core::NormalizeAngle(heading)};
      core::LaserScanTruth truth;
      const core::LaserScan scan = laser.ScanFrom(world, pose, 0.0, -1, &truth);
      const std::vector<core::Segment> segments = core::ExtractLines(scan, extraction);
      acc.Add(ScoreExtraction(scan, truth, section, segments));
    }
  }
  const ExtractionFigures f = acc.Figures();
  Print(name + " (metrics.md)", f);
  return f;
}

// Issue 5 acceptance: TP rate >= 0.95, FP rate <= 0.03, >= 90% of (alpha, r)
// errors inside the 95% gate; 3 noise seeds x 300 (office) or 200 (hall) sensor
// poses per world with 30 visitors. Three seeds are a sample: over six sets of
// three seeds (5-22, docs/benchmarks.md) the hall's TP rate ranged
// 0.950-0.966 (pooled 0.960) and its FP rate 0.021-0.028 (0.025); the
// office's 0.993-0.997 and 0.012-0.014.
TEST(ExtractionScoringTest, OfficeFloorLms200WithVisitors) {
  const ExtractionFigures f = ScoreWorld("office_floor", 30, 300);
  EXPECT_EQ(f.scans, 900);
  EXPECT_GT(f.walls_in_view, 2000);
  EXPECT_GE(f.true_positive_rate, 0.95);   // measured 0.9945
  EXPECT_LE(f.false_positive_rate, 0.03);  // measured 0.0138
  EXPECT_GE(f.in_gate_fraction, 0.90);     // measured 0.9610
}

TEST(ExtractionScoringTest, ExpoHallLms200WithVisitors) {
  const ExtractionFigures f = ScoreWorld("expo_hall", 30, 200);  // 219 free cells
  EXPECT_EQ(f.scans, 600);
  EXPECT_GT(f.walls_in_view, 1200);
  // Walls of surfaces the thesis' sensor model covers: all but the black velvet
  // booth, exhibit 15 (sigma x5 and 30% dropouts, §3.2.4 fig. 3.6), whose
  // faces the adaptive sigma finds in 20 of 62 views — a fit of exactly the
  // velvet readings of each face, segmented by hand, meets the 2 deg / 5 cm
  // criteria in 45: the rest is the noise.
  EXPECT_GE(f.modelled_true_positive_rate, 0.98);  // measured 0.9913
  EXPECT_GE(f.true_positive_rate, 0.95);           // measured 0.9601
  EXPECT_LE(f.false_positive_rate, 0.03);          // measured 0.0281
  EXPECT_GE(f.in_gate_fraction, 0.90);             // measured 0.9540
}

// The rates over six sets of three seeds (5-22) pooled: 3,600 hall scans and
// 5,400 office scans, six times the acceptance test's sample.
TEST(ExtractionScoringTest, SixSeedSetsPooled) {
  const core::LineExtractionOptions preset = core::LineExtractionOptions::SickLms200();
  const ExtractionFigures hall = ScoreWorld("expo_hall", 30, 200, preset, 5, 18);
  EXPECT_EQ(hall.scans, 3600);
  EXPECT_GE(hall.true_positive_rate, 0.95);   // measured 0.9595
  EXPECT_LE(hall.false_positive_rate, 0.03);  // measured 0.0247
  EXPECT_GE(hall.in_gate_fraction, 0.90);
  const ExtractionFigures office = ScoreWorld("office_floor", 30, 300, preset, 5, 18);
  EXPECT_EQ(office.scans, 5400);
  EXPECT_GE(office.true_positive_rate, 0.95);   // measured 0.9947
  EXPECT_LE(office.false_positive_rate, 0.03);  // measured 0.0129
  EXPECT_GE(office.in_gate_fraction, 0.90);
}

// The adaptive sigma is what finds the velvet booth: without it, no face.
TEST(ExtractionScoringTest, ExpoHallVelvetNeedsTheAdaptiveSigma) {
  core::LineExtractionOptions thesis_model = core::LineExtractionOptions::SickLms200();
  thesis_model.adaptive_range_sigma = false;
  const ExtractionFigures without = ScoreWorld("expo_hall", 30, 200, thesis_model);
  const ExtractionFigures with = ScoreWorld("expo_hall", 30, 200);
  const int velvet_without = without.walls_found - without.modelled_walls_found;
  const int velvet_with = with.walls_found - with.modelled_walls_found;
  EXPECT_LE(velvet_without, 3);  // measured 1
  EXPECT_GE(velvet_with, 12);    // measured 20 of 62
  // Elsewhere the noise is nominal and the extraction nearly unchanged.
  EXPECT_NEAR(with.modelled_walls_found, without.modelled_walls_found, 5);
}

}  // namespace
}  // namespace pavilion::scenarios
