#include "scenarios/calibration/calibration_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

std::string Format(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
}

Json Vec3(const Eigen::Vector3d& v) { return Json::array({v[0], v[1], v[2]}); }

Json OdometryJson(const core::EncoderOdometryOptions& o) {
  return Json{{"left_wheel_radius_m", o.left_wheel_radius_m},
              {"right_wheel_radius_m", o.right_wheel_radius_m},
              {"wheelbase_m", o.wheelbase_m},
              {"k_left_m", o.k_left_m},
              {"k_right_m", o.k_right_m}};
}

}  // namespace

std::string CalibrationJson(const OdometryCalibrationReport& r) {
  Json runs = Json::array();
  for (const CalibrationRunReport& row : r.runs) {
    runs.push_back(Json{{"name", row.name},
                        {"kind", RunKindName(row.kind)},
                        {"speed_mps", row.speed_mps},
                        {"wheel_travel_m", row.wheel_travel_m},
                        {"duration_s", row.duration_s},
                        {"error_nominal", Vec3(row.error_nominal)},
                        {"error_calibrated", Vec3(row.error_calibrated)},
                        {"mahalanobis_sq", row.mahalanobis_sq}});
  }
  const core::UmbmarkResult& u = r.umbmark;
  Json j{{"schema", "pavilion.calibration/1"},
         {"robot", r.robot},
         {"options",
          {{"physics_rate_hz", r.options.physics_rate_hz},
           {"runs", r.options.runs},
           {"square_side_m", r.options.square_side_m},
           {"speeds_mps", r.options.speeds_mps},
           {"straight_lengths_m", r.options.straight_lengths_m},
           {"spin_angle_rad", r.options.spin_angle_rad},
           {"arc_radii_m", r.options.arc_radii_m},
           {"floor_friction", r.options.floor_friction},
           {"seed", r.options.seed}}},
         {"simulated_robot",
          {{"wheel_radius_ratio", r.systematic.wheel_radius_ratio},
           {"wheelbase_factor", r.systematic.wheelbase_factor},
           {"encoder_noise", r.encoder_noise},
           {"encoder_k_left_m", r.encoder_k_left_m},
           {"encoder_k_right_m", r.encoder_k_right_m}}},
         {"nominal", OdometryJson(r.nominal)},
         {"calibrated", OdometryJson(r.calibrated)},
         {"estimates",
          {{"straight_scale", r.straight_scale},
           {"umbmark",
            {{"cg_ccw_m", {u.cg_ccw_m.x(), u.cg_ccw_m.y()}},
             {"cg_cw_m", {u.cg_cw_m.x(), u.cg_cw_m.y()}},
             {"one_step",
              {{"corner_overturn_rad", r.umbmark_one_step.corner_overturn_rad},
               {"leg_curvature_rad", r.umbmark_one_step.leg_curvature_rad},
               {"radius_ratio_factor", r.umbmark_one_step.radius_ratio_factor},
               {"turn_factor", r.umbmark_one_step.turn_factor}}},
             {"iterations", r.umbmark_iterations},
             {"corner_overturn_rad", u.corner_overturn_rad},
             {"leg_curvature_rad", u.leg_curvature_rad},
             {"radius_ratio_factor", u.radius_ratio_factor},
             {"turn_factor", u.turn_factor}}},
           {"wheel_radius_ratio",
            r.calibrated.right_wheel_radius_m / r.calibrated.left_wheel_radius_m},
           {"wheelbase_factor", r.calibrated.wheelbase_m / r.nominal.wheelbase_m},
           {"k_m", r.k_m},
           {"k_turn_m", r.k_turn_m},
           {"k_dof", r.k_dof},
           {"e_max_syst_before_m", u.e_max_syst_m},
           {"e_max_syst_after_m", r.e_max_syst_after_m}}},
         {"simulated_s", r.simulated_s},
         {"runs", runs}};
  return j.dump(2) + "\n";
}

std::string OdometryYamlBlock(const OdometryCalibrationReport& r, const std::string& comment) {
  std::ostringstream s;
  s << "odometry:\n";
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) s << "  # " << line << "\n";
  s << "  left_wheel_radius_m: " << Format("%.7f", r.calibrated.left_wheel_radius_m) << "\n";
  s << "  right_wheel_radius_m: " << Format("%.7f", r.calibrated.right_wheel_radius_m) << "\n";
  s << "  wheelbase_m: " << Format("%.6f", r.calibrated.wheelbase_m) << "\n";
  s << "  k_left_m: " << Format("%.3e", r.calibrated.k_left_m) << "\n";
  s << "  k_right_m: " << Format("%.3e", r.calibrated.k_right_m) << "\n";
  s << "  k_turn_m: " << Format("%.3e", r.calibrated.k_turn_m) << "\n";
  return s.str();
}

std::string CalibrationTable(const OdometryCalibrationReport& r) {
  std::ostringstream s;
  char buf[256];
  s << "end-pose errors true - odometry in the start frame (mm, mrad): nominal -> calibrated\n";
  std::snprintf(buf, sizeof buf, "%-14s %5s %7s | %8s %8s %8s | %8s %8s %8s | %6s\n", "run", "m/s",
                "travel", "dx", "dy", "dth", "dx'", "dy'", "dth'", "chi2");
  s << buf;
  for (const CalibrationRunReport& row : r.runs) {
    const Eigen::Vector3d a = row.error_nominal * 1e3, b = row.error_calibrated * 1e3;
    std::snprintf(buf, sizeof buf,
                  "%-14s %5.2f %6.1fm | %8.1f %8.1f %8.1f | %8.1f %8.1f %8.1f | %6.2f\n",
                  row.name.c_str(), row.speed_mps, row.wheel_travel_m, a[0], a[1], a[2], b[0], b[1],
                  b[2], row.mahalanobis_sq);
    s << buf;
  }
  const core::UmbmarkResult& u = r.umbmark;
  const core::UmbmarkResult& o = r.umbmark_one_step;
  std::snprintf(buf, sizeof buf,
                "UMBmark: cg_ccw (%.1f, %.1f) mm, cg_cw (%.1f, %.1f) mm; E_max,syst %.1f mm -> "
                "%.1f mm calibrated\n",
                u.cg_ccw_m.x() * 1e3, u.cg_ccw_m.y() * 1e3, u.cg_cw_m.x() * 1e3,
                u.cg_cw_m.y() * 1e3, u.e_max_syst_m * 1e3, r.e_max_syst_after_m * 1e3);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "  one step: corner over-turn %.3f mrad, leg curvature %.3f mrad, E_d %.5f, turn "
                "factor %.5f\n",
                o.corner_overturn_rad * 1e3, o.leg_curvature_rad * 1e3, o.radius_ratio_factor,
                o.turn_factor);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "  iterated (%d): corner over-turn %.3f mrad, leg curvature %.3f mrad, E_d %.5f, "
                "turn factor %.5f; straight scale %.5f\n",
                r.umbmark_iterations, u.corner_overturn_rad * 1e3, u.leg_curvature_rad * 1e3,
                u.radius_ratio_factor, u.turn_factor, r.straight_scale);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "estimated: r_L %.6f m, r_R %.6f m (ratio %.5f, truth %.5f), b %.5f m "
                "(factor %.5f, truth %.5f)\n",
                r.calibrated.left_wheel_radius_m, r.calibrated.right_wheel_radius_m,
                r.calibrated.right_wheel_radius_m / r.calibrated.left_wheel_radius_m,
                r.systematic.wheel_radius_ratio, r.calibrated.wheelbase_m,
                r.calibrated.wheelbase_m / r.nominal.wheelbase_m, r.systematic.wheelbase_factor);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "           k_L = k_R = %.3e m, k_turn = %.3e m from %d residual dof", r.k_m,
                r.k_turn_m, r.k_dof);
  s << buf;
  if (r.encoder_noise) {
    std::snprintf(buf, sizeof buf, " (encoder noise on: k_L %.3e, k_R %.3e)", r.encoder_k_left_m,
                  r.encoder_k_right_m);
    s << buf;
  }
  s << "\n";
  return s.str();
}

}  // namespace pavilion::scenarios
