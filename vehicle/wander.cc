#include "vehicle/wander.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "terrain/crater.h"
#include "terrain/feature.h"

namespace dt {
namespace {

constexpr double kLegMinS = 3.0, kLegMaxS = 10.0;
constexpr double kLegSpeedMin = 0.25, kLegSpeedMax = 0.6;  // of the type's top speed
constexpr double kLegRateMax = 0.5;                        // of the type's turn rate
constexpr double kTurnBackSpeed = 0.3;                     // of the type's top speed
constexpr double kReactionS = 1.0;  // leg speed held while slowing down (the physical model brakes)
constexpr double kFacingInRad = std::numbers::pi / 3;  // a turn back ends this close to the centre
constexpr double kSteerTimeS = 0.5;  // the turn rate that closes a heading error in this time
// The commanded speed changes by at most this much a second. The light model takes a command at
// once: a step from 5 to 15 m/s in one tick is 300 m/s^2 to dead reckoning, sent in a state that,
// if the next one is lost, a receiver extrapolates for seconds (docs/performance.md).
constexpr double kSpeedRampMps2 = 2.0;

// Obstacles: seen this many seconds of driving ahead (plus a length and a turning circle), passed
// with this much room beside the hull; turning away from them this long at most, then crawling.
constexpr double kAvoidSeeS = 2.0;
constexpr double kAvoidRoomM = 1.0;
constexpr double kAvoidGiveUpS = 8.0;
constexpr double kAvoidSpeed = 0.3;  // of the type's top speed
constexpr double kCrawlSpeed = 0.1;  // of the type's top speed
// A clear path is looked at again after this long (a group's vehicles in turn); one with an
// obstacle every tick.
constexpr double kLookPeriodS = 0.2;

double WrapPi(double a) { return std::remainder(a, 2 * std::numbers::pi); }

// An obstacle as a disc: a crater's own, else the one round its bounds.
void Disc(const Feature& f, double& x_m, double& z_m, double& radius_m) {
  if (f.type() == FeatureType::kCrater) {
    const auto& c = static_cast<const Crater&>(f);
    x_m = c.x_m();
    z_m = c.z_m();
    radius_m = c.radius_m();
    return;
  }
  const Rect b = f.Bounds();
  x_m = (b.min_x + b.max_x) / 2;
  z_m = (b.min_z + b.max_z) / 2;
  radius_m = std::hypot(b.max_x - b.min_x, b.max_z - b.min_z) / 2;
}

}  // namespace

uint64_t WanderRandom::Next() {
  uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double WanderRandom::Uniform(double lo, double hi) {
  const double u = static_cast<double>(Next() >> 11) * 0x1.0p-53;  // [0, 1)
  return lo + (hi - lo) * u;
}

uint64_t WanderSeed(uint64_t group_seed, uint64_t index) {
  WanderRandom r(group_seed ^ (index * 0xd1b54a32d192ed03ULL));
  return r.Next();
}

WanderStart DrawWanderStart(const WanderArea& clear, WanderRandom& random) {
  WanderStart s;
  s.x_m = random.Uniform(clear.x_min_m, clear.x_max_m);
  s.z_m = random.Uniform(clear.z_min_m, clear.z_max_m);
  s.heading_rad = random.Uniform(-std::numbers::pi, std::numbers::pi);
  return s;
}

Wanderer::Wanderer(const VehicleType& type, const WanderArea& area, double terrain_size_x_m,
                   double terrain_size_z_m, uint64_t seed)
    : max_speed_mps_(type.max_speed_mps),
      max_rate_rad_s_(type.max_turn_rate_rad_s),
      length_m_(type.length_m),
      half_width_m_(type.width_m / 2),
      random_(seed),
      look_in_s_(kLookPeriodS * static_cast<double>(seed % 6) / 6.0) {
  const double turn_radius_m = kTurnBackSpeed * max_speed_mps_ / std::max(max_rate_rad_s_, 1e-6);
  turn_radius_m_ = turn_radius_m;
  lookahead_m_ = 2 * turn_radius_m + type.length_m + kLegSpeedMax * max_speed_mps_ * kReactionS;
  edge_margin_m_ = 2 * turn_radius_m + type.length_m;
  // The area less the margin at the terrain's edge; a point at its middle if nothing is left.
  auto clear = [&](double lo, double hi, double terrain_size_m, double& out_lo, double& out_hi) {
    out_lo = std::max(lo, edge_margin_m_);
    out_hi = std::min(hi, terrain_size_m - edge_margin_m_);
    if (out_lo > out_hi) {
      const double mid = std::clamp((lo + hi) / 2, std::min(edge_margin_m_, terrain_size_m / 2),
                                    std::max(terrain_size_m - edge_margin_m_, terrain_size_m / 2));
      out_lo = out_hi = mid;
    }
  };
  clear(area.x_min_m, area.x_max_m, terrain_size_x_m, clear_.x_min_m, clear_.x_max_m);
  clear(area.z_min_m, area.z_max_m, terrain_size_z_m, clear_.z_min_m, clear_.z_max_m);
  NewLeg();
}

void Wanderer::NewLeg() {
  leg_left_s_ = random_.Uniform(kLegMinS, kLegMaxS);
  leg_.speed_mps = max_speed_mps_ * random_.Uniform(kLegSpeedMin, kLegSpeedMax);
  const double turn = random_.Uniform(-1.0, 1.0);
  // One leg in two straight; the others turn by up to kLegRateMax of the type's rate.
  leg_.heading_rate_rad_s = std::abs(turn) < 0.5 ? 0.0 : turn * kLegRateMax * max_rate_rad_s_;
}

bool Wanderer::Inside(double x_m, double z_m) const {
  return x_m >= clear_.x_min_m && x_m <= clear_.x_max_m && z_m >= clear_.z_min_m &&
         z_m <= clear_.z_max_m;
}

double Wanderer::avoid_ahead_m(double speed_mps) const {
  return length_m_ + turn_radius_m_ + std::abs(speed_mps) * kAvoidSeeS;
}

bool Wanderer::ObstacleAhead(const VehiclePose& pose, double ahead_m, const Terrain& terrain,
                             double& at_x_m, double& at_z_m, double& turn_radius_m) const {
  const HeightGrid& g = terrain.ground();
  const double ux = std::cos(pose.heading_rad), uz = std::sin(pose.heading_rad);
  const double ax = pose.x_m, az = pose.z_m;
  const double bx = ax + ux * ahead_m, bz = az + uz * ahead_m;
  const double room_m = half_width_m_ + kAvoidRoomM;
  const Rect path =
      Rect{std::min(ax, bx), std::min(az, bz), std::max(ax, bx), std::max(az, bz)}.Expanded(room_m);
  const double sx = g.size_x_m(), sz = g.size_z_m();
  const SquareIndex lo =
      g.SquareAt(std::clamp(path.min_x, 0.0, sx), std::clamp(path.min_z, 0.0, sz));
  const SquareIndex hi =
      g.SquareAt(std::clamp(path.max_x, 0.0, sx), std::clamp(path.max_z, 0.0, sz));
  double nearest_m = INFINITY;
  for (int j = lo.j; j <= hi.j; ++j) {
    for (int i = lo.i; i <= hi.i; ++i) {
      if (terrain.SquareBits({i, j}) == 0) continue;
      for (const Feature* f : terrain.FeaturesInSquare({i, j})) {
        if (f->type() == FeatureType::kBridge || !f->Bounds().Intersects(path)) continue;
        double cx = 0.0, cz = 0.0, radius_m = 0.0;
        Disc(*f, cx, cz, radius_m);
        // Along the path to the point nearest the disc's centre, and across from it. One behind
        // or beside (passing it, or driving out of one it is on) is no obstacle.
        const double along_m = (cx - ax) * ux + (cz - az) * uz;
        const double across_m = std::abs((cz - az) * ux - (cx - ax) * uz);
        if (along_m <= 0.0 || along_m > ahead_m + radius_m || across_m >= radius_m + room_m ||
            std::hypot(cx - ax, cz - az) <= radius_m)
          continue;
        if (along_m < nearest_m) {
          nearest_m = along_m;
          at_x_m = cx;
          at_z_m = cz;
          // The widest turn that passes it: one that moves `need` sideways in `along` ahead.
          const double need_m = radius_m + room_m - across_m;
          turn_radius_m = along_m * along_m / (2.0 * need_m);
        }
      }
    }
  }
  return nearest_m < INFINITY;
}

WanderCommand Wanderer::Next(const VehiclePose& pose, double dt_s, const Terrain& terrain) {
  const double ax = std::cos(pose.heading_rad), az = std::sin(pose.heading_rad);
  const bool ahead_clear = Inside(pose.x_m + ax * lookahead_m_, pose.z_m + az * lookahead_m_);
  // The bearing to the centre matters only while turning back or about to: most ticks skip its
  // atan2.
  const double error_rad =
      turning_back_ || !ahead_clear
          ? WrapPi(std::atan2((clear_.z_min_m + clear_.z_max_m) / 2 - pose.z_m,
                              (clear_.x_min_m + clear_.x_max_m) / 2 - pose.x_m) -
                   pose.heading_rad)
          : 0.0;
  if (turning_back_ && ahead_clear && std::abs(error_rad) < kFacingInRad) {
    turning_back_ = false;
    NewLeg();
  } else if (!ahead_clear && !turning_back_) {
    turning_back_ = true;
    // The side is kept for the whole turn, so heading straight away from the centre cannot
    // hesitate between the two.
    turn_sign_ = error_rad >= 0.0 ? 1.0 : -1.0;
  }
  WanderCommand wanted = leg_;
  if (turning_back_) {
    // Steered onto the centre once facing it (either side of it, so an overshoot is no turn
    // round), at the full rate on the side chosen until then.
    const double rate =
        std::abs(error_rad) < kFacingInRad ? error_rad / kSteerTimeS : turn_sign_ * max_rate_rad_s_;
    wanted = {kTurnBackSpeed * max_speed_mps_, std::clamp(rate, -max_rate_rad_s_, max_rate_rad_s_)};
  } else {
    leg_left_s_ -= dt_s;
    if (leg_left_s_ <= 0.0) NewLeg();
    wanted = leg_;
  }
  double obstacle_x = 0.0, obstacle_z = 0.0, turn_radius_m = 0.0;
  const double ahead_m = avoid_ahead_m(std::max(pose.speed_mps, speed_mps_));
  look_in_s_ -= dt_s;
  const bool look = avoid_s_ > 0.0 || look_in_s_ <= 0.0;
  if (look && look_in_s_ <= 0.0) look_in_s_ += kLookPeriodS;
  if (look && ObstacleAhead(pose, ahead_m, terrain, obstacle_x, obstacle_z, turn_radius_m)) {
    if (avoid_s_ == 0.0) {
      // Away from the obstacle's centre; the side is kept while avoiding, so two obstacles
      // either side cannot make it hesitate between them.
      const double left = ax * (obstacle_z - pose.z_m) - az * (obstacle_x - pose.x_m);
      avoid_sign_ = left > 0.0 ? -1.0 : 1.0;
    }
    avoid_s_ += dt_s;
    if (avoid_s_ > kAvoidGiveUpS) {
      wanted.speed_mps = std::min(wanted.speed_mps, kCrawlSpeed * max_speed_mps_);
      if (!turning_back_) wanted.heading_rate_rad_s = 0.0;
    } else {
      // Slow enough that the full turn rate's circle passes it, but never below a crawl.
      const double passing_mps =
          std::max(kCrawlSpeed * max_speed_mps_, turn_radius_m * max_rate_rad_s_);
      wanted.speed_mps = std::min({wanted.speed_mps, kAvoidSpeed * max_speed_mps_, passing_mps});
      wanted.heading_rate_rad_s = avoid_sign_ * max_rate_rad_s_;
    }
  } else {
    avoid_s_ = 0.0;
  }
  // Slowing for a turn back or an obstacle may take longer than the ramp allows: it is not
  // ramped down.
  const double step = kSpeedRampMps2 * dt_s;
  speed_mps_ = turning_back_ || avoid_s_ > 0.0
                   ? std::min(wanted.speed_mps, speed_mps_ + step)
                   : std::clamp(wanted.speed_mps, speed_mps_ - step, speed_mps_ + step);
  return {speed_mps_, wanted.heading_rate_rad_s};
}

}  // namespace dt
