// SpriteOf a SimulatedVehicle: the renderer's box for a vehicle of either model.
#pragma once

#include "render/vehicle_sprite.h"
#include "vehicle/simulated_vehicle.h"

namespace dt {

// The hull box (the type's footprint, hull_height_m tall) where the model has it: under the
// physical model the box's underside is the bottom of the running gear under the centre of mass,
// raised by the gear's static sag so a vehicle at rest stands on the surface, turned by the body's
// heading, pitch and roll; under the light model it stands at the vehicle's elevation. A
// destroyed vehicle is drawn in kDeadVehicleColour.
VehicleSprite SpriteOf(const SimulatedVehicle& vehicle, Rgba colour = VehicleSprite{}.colour);

}  // namespace dt
