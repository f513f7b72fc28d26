// BellyGrid: where a vehicle's belly grid points lie (stations ahead by lines across the bottom
// face) and which of them an earthwork's bounds may hold.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vehicle/contact_surface.h"

namespace dt {

class BellyGrid {
 public:
  BellyGrid() = default;
  // Points at most `spacing_m` apart over a footprint `length_m` x `width_m`, `up_m` above the
  // centre of mass (body frame: ahead, up, left; docs/conventions.md), at least two stations and
  // three lines. The points of a centre line (left 0) are left out: the vehicle samples that
  // line at its gear's stations in every step.
  BellyGrid(double length_m, double width_m, double spacing_m, double up_m);

  int stations() const { return stations_; }
  int lines() const { return lines_; }
  double station_step_m() const { return station_step_m_; }
  double line_step_m() const { return line_step_m_; }
  bool OnCentreLine(int line) const;
  // The point at (station, line), body frame.
  Eigen::Vector3d Body(int station, int line) const;

  // The vehicle's contact at (station, line): -1 outside the grid or on the centre line.
  int ContactAt(int station, int line) const;
  void SetContact(int station, int line, int contact);

  // Sets marks[contact] to 1 for every point whose plan position x + R * Body(...) may lie inside
  // the bounds of one of `near`; every point that lies inside is marked. `marks` is indexed by
  // contact and left as it is elsewhere.
  void MarkUnder(const Eigen::Vector3d& x, const Eigen::Matrix3d& R,
                 std::span<const NearEarthwork> near, std::span<uint8_t> marks) const;

 private:
  int stations_ = 0, lines_ = 0;
  double length_m_ = 0.0, width_m_ = 0.0, up_m_ = 0.0;
  double station_step_m_ = 0.0, line_step_m_ = 0.0;
  std::vector<int> contacts_;  // station * lines_ + line
};

}  // namespace dt
