// Berm operations: breaching a berm into shorter berms, and laying out an emplacement of three.
#pragma once

#include <array>
#include <vector>

#include "base/result.h"
#include "terrain/berm.h"
#include "terrain/feature_params.h"

namespace dt {

// Breach (thesis III.C.2, second method): the parameters of the 0, 1 or 2 shorter berms that
// replace `berm` when a gap of `gap_width_m` is cut centred `gap_centre_m` along its crest from
// the placement point. The gap is bare ground across its whole width: each piece stops, end
// piece included, at the gap's edge; a piece whose crest would be shorter than kMinFeatureSizeM
// is dropped. Pieces keep the berm's direction, width, height and material (a kFromGround piece
// takes the soil under its own placement point; use the Berm overload to keep the resolved
// material). Refused if `berm` is not a valid berm, the gap width is not finite and > 0, or the
// gap centre is not on the crest [0, length].
Result<std::vector<FeatureParams>> BreachBerm(const FeatureParams& berm, double gap_centre_m,
                                              double gap_width_m);
// As above; the pieces carry the berm's resolved material so they look like the original.
Result<std::vector<FeatureParams>> BreachBerm(const Berm& berm, double gap_centre_m,
                                              double gap_width_m);

// An emplacement (thesis fig. 7): three berms whose crests form a U around the centre, open to
// the rear. The front crest stands size_m / 2 ahead of the centre across the facing direction;
// the side crests run back from its ends for size_m. Crest ends meet at the front corners.
struct EmplacementSpec {
  double centre_x_m = 0.0;
  double centre_z_m = 0.0;
  double facing_rad = 0.0;  // from the centre toward the front berm (docs/conventions.md)
  double size_m = 0.0;      // crest length of each berm
  double width_m = 0.0;
  double height_m = 0.0;
  Material material = Material::kFromGround;
};

// Returns {front, left, right}: the front berm runs right to left, the side berms run from the
// front corners backwards. Refused (naming the value) if any berm's parameters are invalid.
Result<std::array<FeatureParams, 3>> EmplacementBerms(const EmplacementSpec& spec);

}  // namespace dt
