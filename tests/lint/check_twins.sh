#!/usr/bin/env bash
# Fails when a removed duplicate comes back (issue 13): the robot type twins,
# and the one-home helpers re-implemented elsewhere.
#   - types: RobotSpec, SimRobotSetup, LaserMountSetup, core::EncoderOdometryOptions
#     (one robot type chain: RobotDescription -> RobotConfig -> RobotEntry -> SimRobot;
#     the odometry model is core::EncoderOdometryOptions)
#   - angle wrapping: std::remainder / fmod by 2 pi only in core/types/pose2.cc
#     (core::NormalizeAngle)
#   - encoder ticks -> wheel travel (2 pi / ticks_per_revolution) only in
#     core/localization/encoder_odometry.cc (core::WheelTravelFromEncoders)
#   - point-segment distance only in core/geometry/ (core::PointSegmentDistance)
# Usage: check_twins.sh ROOT
set -u
root=${1:-.}
cd "$root" || exit 2
status=0
mapfile -t files < <(find core nav sim scenarios -name '*.h' -o -name '*.cc' 2>/dev/null | sort)

report() {  # report WHAT HITS
  if [ -n "$2" ]; then
    echo "twin: $1"
    echo "$2"
    status=1
  fi
}

report "a removed robot type name (use RobotConfig / SimRobot / LaserMount / core::EncoderOdometryOptions)" \
  "$(grep -HnwE 'RobotSpec|SimRobotSetup|LaserMountSetup|OdometryCalibration' "${files[@]}")"
report "angle wrapping outside core::NormalizeAngle (core/types/pose2.cc)" \
  "$(grep -HnE '(remainder|fmod)\([^;]*(2(\.0)? \* (std::numbers::)?pi|kTwoPi|2 \* kPi|2\.0 \* kPi)' "${files[@]}" |
     grep -v '^core/types/pose2.cc:')"
report "encoder ticks to wheel travel outside core::WheelTravelFromEncoders" \
  "$(grep -HnE 'pi\)? */ *[a-z_.>-]*ticks_per_revolution' "${files[@]}" |
     grep -v '^core/localization/encoder_odometry.cc:')"
report "point-segment distance outside core/geometry/" \
  "$(grep -HnE '^[A-Za-z].*\bPointSegmentDistance\(' "${files[@]}" | grep -v '^core/geometry/' |
     grep -E '^[^:]+:[0-9]+:(static |inline )?double ')"
if [ $status -eq 0 ]; then echo "no twins (${#files[@]} files)"; fi
exit $status
