#include "vehicle/belly_grid.h"

#include <algorithm>
#include <cmath>

namespace dt {
namespace {

// An earthwork's bounds, widened by this against the rounding of plan positions.
constexpr double kBoundsSlackM = 1e-6;
// A line whose stations move less than this along a plan axis per station is taken as constant
// along it, within kFlatSlackM (far more than the stations' drift along it).
constexpr double kFlatStepM = 1e-6;
constexpr double kFlatSlackM = 1e-4;
// Station intervals are clamped this far past the grid before they become integers.
constexpr double kStationClampMargin = 2.0;

}  // namespace

BellyGrid::BellyGrid(double length_m, double width_m, double spacing_m, double up_m)
    : stations_(std::max(2, static_cast<int>(std::ceil(length_m / spacing_m)) + 1)),
      lines_(std::max(3, static_cast<int>(std::ceil(width_m / spacing_m)) + 1)),
      length_m_(length_m),
      width_m_(width_m),
      up_m_(up_m),
      station_step_m_(length_m / (stations_ - 1)),
      line_step_m_(width_m / (lines_ - 1)),
      contacts_(static_cast<size_t>(stations_ * lines_), -1) {}

bool BellyGrid::OnCentreLine(int line) const {
  return std::abs(-width_m_ / 2.0 + width_m_ * line / (lines_ - 1)) < 1e-9;
}

Eigen::Vector3d BellyGrid::Body(int station, int line) const {
  return {-length_m_ / 2.0 + length_m_ * station / (stations_ - 1), up_m_,
          -width_m_ / 2.0 + width_m_ * line / (lines_ - 1)};
}

int BellyGrid::ContactAt(int station, int line) const {
  if (station < 0 || station >= stations_ || line < 0 || line >= lines_) return -1;
  return contacts_[static_cast<size_t>(station * lines_ + line)];
}

void BellyGrid::SetContact(int station, int line, int contact) {
  contacts_[static_cast<size_t>(station * lines_ + line)] = contact;
}

void BellyGrid::MarkUnder(const Eigen::Vector3d& x, const Eigen::Matrix3d& R,
                          std::span<const NearEarthwork> near, std::span<uint8_t> marks) const {
  // Along one line a point's plan position is linear in its station, so a rectangle holds the
  // points of an interval of stations. Widened by a station each way, the interval holds every
  // point that x + R * Body puts inside, whatever the two forms' rounding.
  const Eigen::Vector3d per_station = R.col(0) * station_step_m_;
  for (const NearEarthwork& e : near) {
    const Rect b = e.bounds.Expanded(kBoundsSlackM);
    for (int line = 0; line < lines_; ++line) {
      const Eigen::Vector3d first = x + R * Body(0, line);
      double lo = -1e6, hi = 1e6;  // stations, far beyond any grid
      bool off_line = false;
      auto clip = [&](double at, double step, double min, double max) {
        if (std::abs(step) < kFlatStepM) {
          off_line = off_line || at < min - kFlatSlackM || at > max + kFlatSlackM;
          return;
        }
        const double t0 = (min - at) / step, t1 = (max - at) / step;
        lo = std::max(lo, std::min(t0, t1));
        hi = std::min(hi, std::max(t0, t1));
      };
      clip(first.x(), per_station.x(), b.min_x, b.max_x);
      clip(first.z(), per_station.z(), b.min_z, b.max_z);
      if (off_line || !(lo <= hi + 2.0)) continue;
      const int s0 =
          std::max(0, static_cast<int>(std::floor(std::max(lo, -kStationClampMargin))) - 1);
      const int s1 =
          std::min(stations_ - 1,
                   static_cast<int>(std::ceil(std::min(hi, stations_ + kStationClampMargin))) + 1);
      for (int s = s0; s <= s1; ++s) {
        const int k = contacts_[static_cast<size_t>(s * lines_ + line)];
        if (k >= 0) marks[static_cast<size_t>(k)] = 1;
      }
    }
  }
}

}  // namespace dt
