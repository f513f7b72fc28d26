#include "dis/dead_reckoning.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dt::dis {
namespace {

using Mat = std::array<std::array<double, 3>, 3>;

// R = Rz(psi) Ry(theta) Rx(phi): body axes (columns) in geocentric axes.
Mat RotationOf(const EulerAngles& e) {
  const double cps = std::cos(e.psi), sps = std::sin(e.psi);
  const double ct = std::cos(e.theta), st = std::sin(e.theta);
  const double cph = std::cos(e.phi), sph = std::sin(e.phi);
  return {{{cps * ct, cps * st * sph - sps * cph, cps * st * cph + sps * sph},
           {sps * ct, sps * st * sph + cps * cph, sps * st * cph - cps * sph},
           {-st, ct * sph, ct * cph}}};
}

EulerAngles AnglesOf(const Mat& r) {
  const double theta = std::asin(std::clamp(-r[2][0], -1.0, 1.0));
  double psi, phi;
  if (std::abs(r[2][0]) < 1.0 - 1e-12) {
    psi = std::atan2(r[1][0], r[0][0]);
    phi = std::atan2(r[2][1], r[2][2]);
  } else {
    phi = 0.0;
    psi = std::atan2(-r[0][1], r[1][1]);
  }
  return {static_cast<float>(psi), static_cast<float>(theta), static_cast<float>(phi)};
}

Mat Multiply(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
    }
  }
  return c;
}

// Rotation by angle |w| dt about w (Rodrigues).
Mat AxisAngle(const Vector3F& w, double dt_s) {
  const double wx = w.x, wy = w.y, wz = w.z;
  const double rate = std::sqrt(wx * wx + wy * wy + wz * wz);
  Mat r{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  if (rate * std::abs(dt_s) < 1e-15) return r;
  const double angle = rate * dt_s;
  const double x = wx / rate, y = wy / rate, z = wz / rate;
  const double c = std::cos(angle), s = std::sin(angle), v = 1.0 - c;
  return {{{c + x * x * v, x * y * v - z * s, x * z * v + y * s},
           {y * x * v + z * s, c + y * y * v, y * z * v - x * s},
           {z * x * v - y * s, z * y * v + x * s, c + z * z * v}}};
}

bool Rotates(uint8_t algorithm) {
  return algorithm == static_cast<uint8_t>(DeadReckoningAlgorithm::kRpw) ||
         algorithm == static_cast<uint8_t>(DeadReckoningAlgorithm::kRvw);
}

}  // namespace

WorldCoordinates ExtrapolatedLocation(const EntityStatePdu& pdu, double dt_s) {
  const auto algorithm = static_cast<DeadReckoningAlgorithm>(pdu.dead_reckoning.algorithm);
  WorldCoordinates p = pdu.location;
  const Vector3F& v = pdu.linear_velocity;
  const Vector3F& a = pdu.dead_reckoning.linear_acceleration;
  switch (algorithm) {
    case DeadReckoningAlgorithm::kFpw:
    case DeadReckoningAlgorithm::kRpw:
      p.x += v.x * dt_s;
      p.y += v.y * dt_s;
      p.z += v.z * dt_s;
      break;
    case DeadReckoningAlgorithm::kRvw:
    case DeadReckoningAlgorithm::kFvw: {
      const double half = 0.5 * dt_s * dt_s;
      p.x += v.x * dt_s + a.x * half;
      p.y += v.y * dt_s + a.y * half;
      p.z += v.z * dt_s + a.z * half;
      break;
    }
    default:
      break;  // static, other, and the body-coordinate algorithms stay put
  }
  return p;
}

EulerAngles ExtrapolatedOrientation(const EntityStatePdu& pdu, double dt_s) {
  if (!Rotates(pdu.dead_reckoning.algorithm)) return pdu.orientation;
  // Body rates: the rotation applies on the body side, R(t) = R0 * exp([w] dt).
  return AnglesOf(
      Multiply(RotationOf(pdu.orientation), AxisAngle(pdu.dead_reckoning.angular_velocity, dt_s)));
}

double OrientationDifferenceRad(const EulerAngles& a, const EulerAngles& b) {
  const Mat ra = RotationOf(a), rb = RotationOf(b);
  // trace(Ra^T Rb) = 1 + 2 cos(angle)
  double trace = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) trace += ra[k][i] * rb[k][i];
  }
  return std::acos(std::clamp((trace - 1.0) / 2.0, -1.0, 1.0));
}

UpdateReason UpdateDue(const EntityStatePdu& last, double seconds_since_sent,
                       const EntityStatePdu& current, const DeadReckoningThresholds& t) {
  if (last.dead_reckoning.algorithm != current.dead_reckoning.algorithm ||
      last.appearance != current.appearance || last.entity_type != current.entity_type ||
      last.force_id != current.force_id || last.marking != current.marking ||
      last.capabilities != current.capabilities) {
    return UpdateReason::kChange;
  }
  const WorldCoordinates p = ExtrapolatedLocation(last, seconds_since_sent);
  const double dx = p.x - current.location.x, dy = p.y - current.location.y,
               dz = p.z - current.location.z;
  if (dx * dx + dy * dy + dz * dz > t.position_m * t.position_m) return UpdateReason::kPosition;
  if (OrientationDifferenceRad(ExtrapolatedOrientation(last, seconds_since_sent),
                               current.orientation) > t.orientation_rad) {
    return UpdateReason::kOrientation;
  }
  if (seconds_since_sent >= t.heartbeat_s) return UpdateReason::kHeartbeat;
  return UpdateReason::kNone;
}

}  // namespace dt::dis
