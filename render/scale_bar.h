// Scale bar: a labelled bar of round length in a map image's lower-left corner.
#pragma once

#include <string>

#include "render/image.h"

namespace dt {

// The round length (1, 2 or 5 times a power of ten metres) closest below `max_length_m`.
// Throws std::invalid_argument unless max_length_m > 0 and finite.
double RoundScaleLengthM(double max_length_m);
// "500 m", "2 km", "0.5 m".
std::string ScaleLabel(double length_m);

// Draws a bar at most a fifth of the image wide on a white panel, with its length written above
// it. Throws std::invalid_argument unless metres_per_pixel > 0 and finite.
void DrawScaleBar(Image& image, double metres_per_pixel);

}  // namespace dt
