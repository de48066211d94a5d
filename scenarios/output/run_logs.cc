#include "scenarios/output/run_logs.h"

#include "scenarios/output/csv_row.h"

namespace pavilion::scenarios {

TrajectoryLog::TrajectoryLog(const std::string& path) : writer_(path) {
  writer_.Append(
      "time_s,id,true_x_m,true_y_m,true_theta_rad,odom_x_m,odom_y_m,odom_theta_rad,est_x_m,est_y_"
      "m,est_theta_rad,cov_xx,cov_xy,cov_xtheta,cov_yy,cov_ytheta,cov_thetatheta");
}

void TrajectoryLog::AddBody(double time_s, const std::string& id, const core::Pose2& p) {
  writer_.Append(CsvRow()
                     .Add(time_s, 3)
                     .Add(id)
                     .Add(p.x_m, 6)
                     .Add(p.y_m, 6)
                     .Add(p.theta_rad, 6)
                     .Empty(12)
                     .str());
}

void TrajectoryLog::AddPeople(double time_s, const std::vector<sim::crowd::PersonState>& people,
                              const std::vector<std::string>& ids) {
  for (std::size_t i = 0; i < people.size(); ++i) {
    const sim::crowd::PersonState& p = people[i];
    if (p.present) AddBody(time_s, ids[i], {p.position_m.x(), p.position_m.y(), p.heading_rad});
  }
}

void TrajectoryLog::AddRobot(double time_s, const std::string& id, const core::Pose2& p,
                             const core::Pose2& o, const core::PoseWithCovariance* estimate) {
  CsvRow row;
  row.Add(time_s, 3)
      .Add(id)
      .Add(p.x_m, 6)
      .Add(p.y_m, 6)
      .Add(p.theta_rad, 6)
      .Add(o.x_m, 6)
      .Add(o.y_m, 6)
      .Add(o.theta_rad, 6);
  if (estimate) {
    const core::Pose2& e = estimate->pose;
    row.Add(e.x_m, 6).Add(e.y_m, 6).Add(e.theta_rad, 6).Covariance(estimate->covariance);
  } else {
    row.Empty(9);
  }
  writer_.Append(row.str());
}

LocalizationLog::LocalizationLog(const std::string& path) : writer_(path) {
  writer_.Append(
      "time_s,id,cycle,true_x_m,true_y_m,true_theta_rad,est_x_m,est_y_m,est_theta_rad,cov_xx,"
      "cov_xy,cov_xtheta,cov_yy,cov_ytheta,cov_thetatheta,position_error_m,heading_error_rad,"
      "nees,two_sigma_frontal_m,two_sigma_lateral_m,two_sigma_heading_rad,predictions,"
      "observations,matched_lines,matched_beacons,lost,state,hypotheses,matched_edges");
}

void LocalizationLog::Add(const std::string& id, std::int64_t index, const LocalizationCycle& c) {
  writer_.Append(CsvRow()
                     .Add(c.time_s, 3)
                     .Add(id)
                     .Add(index)
                     .Add(c.truth.x_m, 6)
                     .Add(c.truth.y_m, 6)
                     .Add(c.truth.theta_rad, 6)
                     .Add(c.estimate.x_m, 6)
                     .Add(c.estimate.y_m, 6)
                     .Add(c.estimate.theta_rad, 6)
                     .Covariance(c.covariance)
                     .Add(c.position_error_m, 6)
                     .Add(c.heading_error_rad, 6)
                     .Add(c.nees, 4)
                     .Add(c.two_sigma_frontal_m, 6)
                     .Add(c.two_sigma_lateral_m, 6)
                     .Add(c.two_sigma_heading_rad, 6)
                     .Add(std::int64_t{c.predictions})
                     .Add(std::int64_t{c.observations})
                     .Add(std::int64_t{c.matched_lines})
                     .Add(std::int64_t{c.matched_beacons})
                     .Add(std::int64_t{c.lost ? 1 : 0})
                     .Add(std::string(nav::LocalizationModeName(c.mode)))
                     .Add(std::int64_t{c.hypotheses})
                     .Add(std::int64_t{c.matched_edges})
                     .str());
}

}  // namespace pavilion::scenarios
