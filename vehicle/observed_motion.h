// ObserveVehicle: feeds a simulated vehicle's pose (and, under the physical model, its own
// velocities) to the MotionEstimator its owner reports rates from.
#pragma once

#include "vehicle/dead_reckoning.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// The vehicle's pose as dead reckoning sees it: the ground contact under its centre
// (VehiclePose: x, elevation, z) and its orientation.
DrPose DrPoseOf(const SimulatedVehicle& vehicle);

// Physical model: its velocity and angular velocity (the latter in the body frame); light model:
// differences of poses.
void ObserveVehicle(MotionEstimator& estimator, const SimulatedVehicle& vehicle, double t_s);

}  // namespace dt
