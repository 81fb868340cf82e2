#include "hexapod_fw/gait.hpp"

#include <math.h>

namespace hexapod_fw {

namespace {

struct Vec3 {
  double x, y, z;
};

constexpr double kInvTwoA2A3 = 1.0 / (2.0 * kLinkA2 * kLinkA3);
constexpr double kInvA1 = 1.0 / kLinkA1;
constexpr double kInvA2 = 1.0 / kLinkA2;
constexpr double kInvA3 = 1.0 / kLinkA3;
constexpr double kPerPositionUnit = 1.0 / kPositionUnit;  // 5000
constexpr double kPerVelocityUnit = 1.0 / kVelocityUnit;  // 1000

// numpy's round(x, 12): scale, round half to even, scale back.
double round_time(double x) {
  const double scale = 1e12;  // 10 ** kTimeDecimals
  static_assert(kTimeDecimals == 12, "round_time's scale follows kTimeDecimals");
  return nearbyint(x * scale) / scale;
}

// numpy's mod for a positive divisor: the result has the divisor's sign.
double np_mod(double a, double b) {
  double m = fmod(a, b);
  if (m != 0.0 && m < 0.0) m += b;
  return m;
}

int16_t quantise(double value, double per_unit) {
  double q = nearbyint(value * per_unit);
  if (q > 32767.0) q = 32767.0;
  if (q < -32767.0) q = -32767.0;
  return static_cast<int16_t>(q);
}

struct KeyPoints {
  Vec3 start, mid, end;
  double t_support, t_support_rounded, t_swing;
  Vec3 support_velocity;  // (end - start) / t_support; zero without support
  double inv_swing;       // 1 / swing time (1 without swing)
};

KeyPoints key_points(const double* v, const LegMount& m, int leg) {
  const double radius = v[kRadius + leg], offset = v[kAngleOffset + leg];
  const double cx = radius * cos(offset), cy = radius * sin(offset);
  const double cos_yaw = cos(m.yaw), sin_yaw = sin(m.yaw);
  // the body's velocity at the foot-path centre, in base_link: v (cos a, sin a) + omega z x c
  const double base_cx = m.x + cos_yaw * cx - sin_yaw * cy;
  const double base_cy = m.y + sin_yaw * cx + cos_yaw * cy;
  const double turn = v[kTurnRate];
  const double vx = v[kBodyVelocity] * cos(v[kCrabAngle]) - turn * base_cy;
  const double vy = v[kBodyVelocity] * sin(v[kCrabAngle]) + turn * base_cx;
  const double scale = v[kPeriod] * v[kDutyFactor + leg];
  const double half_x = 0.5 * scale * (cos_yaw * vx + sin_yaw * vy);
  const double half_y = 0.5 * scale * (-sin_yaw * vx + cos_yaw * vy);
  const double ground = -(v[kBodyHeight] + m.z);
  KeyPoints k = {};
  k.start = {cx + half_x, cy + half_y, ground};
  k.mid = {cx, cy, ground + v[kStepHeight + leg]};
  k.end = {cx - half_x, cy - half_y, ground};
  const double period = v[kPeriod];
  k.t_support = v[kDutyFactor + leg] * period;
  k.t_support_rounded = round_time(k.t_support);
  k.t_swing = period - k.t_support;
  if (k.t_support > 0.0) {
    k.support_velocity = {(k.end.x - k.start.x) / k.t_support,
                          (k.end.y - k.start.y) / k.t_support,
                          (k.end.z - k.start.z) / k.t_support};
  }
  k.inv_swing = 1.0 / (k.t_swing > 0.0 ? k.t_swing : 1.0);
  return k;
}

// Foot position and velocity of one leg at cycle time t (thesis eqs. 3.19-3.36). The leg's own
// cycle time and the support/swing decision use hexapod_gait's exact operations (the phase
// boundaries must fall on the same side); the rest may round differently.
void foot(const double* v, int leg, const KeyPoints& k, double t, Vec3& p, Vec3& dp) {
  const double period = v[kPeriod];
  double tau = np_mod(t / period - v[kPhaseOffset + leg], 1.0) * period;
  tau = np_mod(round_time(tau), period);
  if (tau < k.t_support_rounded) {  // support: a straight line at constant velocity
    dp = k.support_velocity;
    p = {k.start.x + dp.x * tau, k.start.y + dp.y * tau, k.start.z + dp.z * tau};
    return;
  }
  // swing: the 6th-order polynomial end -> mid -> start, in normalised time s
  double s = (tau - k.t_support) * k.inv_swing;
  s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
  const double s2 = s * s, s3 = s2 * s, om = 1.0 - s;
  const double pm = 64.0 * s3 * (om * om * om);
  const double pe = s3 * (-22.0 + s * (81.0 + s * (-90.0 + 32.0 * s)));
  const double dpm = 192.0 * s2 * (om * om) * (1.0 - 2.0 * s) * k.inv_swing;
  const double dpe = s2 * (-66.0 + s * (324.0 + s * (-450.0 + 192.0 * s))) * k.inv_swing;
  const Vec3 dm = {k.mid.x - k.end.x, k.mid.y - k.end.y, k.mid.z - k.end.z};
  const Vec3 de = {k.start.x - k.end.x, k.start.y - k.end.y, k.start.z - k.end.z};
  p = {k.end.x + dm.x * pm + de.x * pe, k.end.y + dm.y * pm + de.y * pe,
       k.end.z + dm.z * pm + de.z * pe};
  dp = {dm.x * dpm + de.x * dpe, dm.y * dpm + de.y * dpe, dm.z * dpm + de.z * dpe};
}

// Closed-form IK (eqs. 3.38-3.43, knee down), its FK check and the joint rates (3.44-3.46).
// The sines and cosines of the joint angles come from the triangles the atan2 calls were given
// (identities, no sin/cos calls): with soft-float doubles on a Cortex-M4 each libm call costs
// thousands of instructions. They agree with cos(atan2(...)) to rounding.
bool leg_joints(const Vec3& p, const Vec3& dp, double q[3], double w[3]) {
  const double a1 = kLinkA1, a2 = kLinkA2, a3 = kLinkA3;
  const double t1 = atan2(p.y, p.x);
  const double r1 = sqrt(p.x * p.x + p.y * p.y);
  const double inv_r1 = r1 > 0.0 ? 1.0 / r1 : 0.0;
  const double c1 = r1 > 0.0 ? p.x * inv_r1 : 1.0, s1 = p.y * inv_r1;  // atan2(0, 0) = 0
  const double rx = p.x - a1 * c1, ry = p.y - a1 * s1;
  const double rho2 = rx * rx + ry * ry;
  const double rho = sqrt(rho2);
  double c3 = (rho2 + p.z * p.z - a2 * a2 - a3 * a3) * kInvTwoA2A3;
  c3 = c3 < -1.0 ? -1.0 : (c3 > 1.0 ? 1.0 : c3);
  const double s3 = -sqrt(1.0 - c3 * c3);
  // t2 = A - B with A = atan2(z, rho) and B = atan2(a3 s3, a2 + a3 c3)
  const double bx = a2 + a3 * c3, by = a3 * s3;
  const double t2 = atan2(p.z, rho) - atan2(by, bx);
  const double t3 = atan2(s3, c3);
  const double ra = sqrt(rho2 + p.z * p.z), rb = sqrt(bx * bx + by * by);
  const double inv_ra = ra > 0.0 ? 1.0 / ra : 0.0, inv_rb = rb > 0.0 ? 1.0 / rb : 0.0;
  const double ca = ra > 0.0 ? rho * inv_ra : 1.0, sa = p.z * inv_ra;
  const double cb = rb > 0.0 ? bx * inv_rb : 1.0, sb = by * inv_rb;
  const double c2 = ca * cb + sa * sb, s2 = sa * cb - ca * sb;
  const double c23 = c2 * c3 - s2 * s3, s23 = s2 * c3 + c2 * s3;
  // forward kinematics of the solution: a point out of reach misses
  const double reach = a1 + a3 * c23 + a2 * c2;
  const double ex = c1 * reach - p.x, ey = s1 * reach - p.y, ez = a3 * s23 + a2 * s2 - p.z;
  const double miss2 = ex * ex + ey * ey + ez * ez;  // squared: no sqrt needed to compare
  if (miss2 > kReachTolerance * kReachTolerance) return false;  // as hexapod_gait
  const double margin_a = fabs(s3), margin_b = fabs(reach) * kInvA1;
  if ((margin_a < margin_b ? margin_a : margin_b) < kSingularityTolerance) return false;
  const double radial = dp.z * s2 + dp.x * c1 * c2 + dp.y * c2 * s1;
  const double tangential = dp.z * c2 - dp.x * c1 * s2 - dp.y * s1 * s2;
  q[0] = t1;
  q[1] = t2;
  q[2] = t3;
  const double inv_s3 = 1.0 / s3;
  w[0] = (dp.y * c1 - dp.x * s1) / reach;
  w[1] = (tangential + c3 * inv_s3 * radial) * kInvA2;
  w[2] = -(tangential + (a2 + a3 * c3) * inv_s3 * kInvA3 * radial) * kInvA2;
  return true;
}

}  // namespace

int rows_for_period(double period) {
  const double n = period * kRobotRate;
  const double steps = nearbyint(n);
  const double tolerance = 1e-6 * (n > 1.0 ? n : 1.0);
  if (!(steps >= 2.0) || fabs(n - steps) > tolerance || steps > kMaxRows) return 0;
  return static_cast<int>(steps);
}

bool slot_mounts(const uint8_t leg_map[kLegs], LegMount mounts[kLegs]) {
  int urdf_leg_of_slot[kLegs] = {-1, -1, -1, -1, -1, -1};
  for (int k = 0; k < kLegs; ++k) {
    const int slot = leg_map[k] - 1;
    if (slot < 0 || slot >= kLegs || urdf_leg_of_slot[slot] >= 0) return false;
    urdf_leg_of_slot[slot] = k;
  }
  for (int s = 0; s < kLegs; ++s) mounts[s] = kMounts[urdf_leg_of_slot[s]];
  return true;
}

BuildResult build_table(const double* values, const LegMount* mounts, GaitTable& table) {
  const int rows = rows_for_period(values[kPeriod]);
  if (rows == 0) return BuildResult::kBadPeriod;
  KeyPoints keys[kLegs];
  for (int leg = 0; leg < kLegs; ++leg) keys[leg] = key_points(values, mounts[leg], leg);
  for (int row = 0; row < rows; ++row) {
    const double t = row / kRobotRate;
    for (int leg = 0; leg < kLegs; ++leg) {
      Vec3 p, dp;
      foot(values, leg, keys[leg], t, p, dp);
      double q[3], w[3];
      if (!leg_joints(p, dp, q, w)) return BuildResult::kUnreachable;
      for (int j = 0; j < 3; ++j) {
        table.position[row][3 * leg + j] = quantise(q[j], kPerPositionUnit);
        table.velocity[row][3 * leg + j] = quantise(w[j], kPerVelocityUnit);
      }
    }
  }
  table.rows = static_cast<uint16_t>(rows);
  return BuildResult::kOk;
}

}  // namespace hexapod_fw
