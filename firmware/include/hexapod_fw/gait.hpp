// The thesis gait controller (section 3.4, as hexapod_gait implements it): the joint table of
// one gait cycle at the robot's 120 Hz from the 36 protocol parameters, with the IK
// reachability and singularity checks of section 3.4.5. Computed in double precision (as
// hexapod_gait, so both take the same decisions), stored in 16-bit fixed point.
#pragma once
#include <stdint.h>

#include "hexapod_fw/generated.hpp"

namespace hexapod_fw {

constexpr int kLegs = 6;
constexpr int kJoints = 3 * kLegs;
// Longest cycle: the period's upper bound at 120 Hz.
constexpr int kMaxRows = static_cast<int>(kMaxPeriod * kRobotRate + 0.5);
// Stored units: positions in 1/5000 rad (range +-6.55 rad), rates in 1/1000 rad/s (+-32.7).
constexpr double kPositionUnit = 2e-4;
constexpr double kVelocityUnit = 1e-3;

// Parameter slots (PARAM_NAMES in hexapod_bridge.extension).
enum Param : int {
  kBodyVelocity = 0,
  kBodyHeight = 1,
  kPeriod = 2,
  kCrabAngle = 3,
  kRadius = 4,        // + leg - 1
  kAngleOffset = 10,  // + leg - 1
  kStepHeight = 16,   // + leg - 1
  kDutyFactor = 22,   // + leg - 1
  kPhaseOffset = 28,  // + leg - 1
  kArchiveIndex = 34,
  kTurnRate = 35,
};

enum class BuildResult : uint8_t {
  kOk,
  kBadPeriod,    // period x 120 Hz is not a whole number of at least 2 rows
  kUnreachable,  // a foot point is out of reach or on a singularity
};

struct GaitTable {
  uint16_t rows;
  int16_t position[kMaxRows][kJoints];  // joints leg-major: coxa, femur, tibia
  int16_t velocity[kMaxRows][kJoints];

  float position_rad(int row, int joint) const {
    return static_cast<float>(position[row][joint] * kPositionUnit);
  }
  float velocity_rad_s(int row, int joint) const {
    return static_cast<float>(velocity[row][joint] * kVelocityUnit);
  }
};

// Rows of one cycle for this period, or 0 if the period is not a whole number of >= 2 rows.
int rows_for_period(double period);

// Fill ``table`` from ``values`` (kParams, range-checked by the caller). On failure the table's
// contents are undefined: the caller rebuilds the last good gait.
// Leg mounts of the robot's slots: slot s (0-based) is the URDF leg k with leg_map[k] = s + 1
// (bridge_node's leg_map: the robot's leg number of each URDF leg). False if leg_map is not a
// permutation of 1..6 (then mounts is left alone).
bool slot_mounts(const uint8_t leg_map[kLegs], LegMount mounts[kLegs]);

// The 120 Hz table of ``values`` (per-leg values in the robot's slots), each slot's leg mounted
// at ``mounts`` (slot_mounts).
BuildResult build_table(const double* values, const LegMount* mounts, GaitTable& table);

}  // namespace hexapod_fw
