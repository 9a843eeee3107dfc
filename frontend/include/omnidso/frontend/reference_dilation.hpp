#pragma once
// One pass of dilation of a pyramid level's sparse inverse-distance map (DSO's coarse tracker
// does the same to its reference): every pixel that holds no point but has a point among its
// neighbours becomes a point of its own, at the mean inverse distance of those neighbours,
//
//   d(p) = (1 / |N(p) ∩ P|) Σ_{q ∈ N(p) ∩ P} d(q),   p ∉ P, N(p) ∩ P ≠ ∅,
//
// P the level's points before the pass (a new point never feeds another), N(p) the four
// diagonal neighbours (p ± (1, 1), p ± (1, −1)) or the four direct ones (p ± (1, 0),
// p ± (0, 1)). Pixels within one of the image's edge, or outside the level's content mask
// when one is given, are never added.
//
// Why: the tracker's residuals sit only where the reference has points, so a sparse
// reference gives each level few terms and a cost with narrow valleys; a frame turned well
// past the hypotheses (H12p at 10 Hz, 19° in one frame of a 90° view) started outside the
// true pose's valley and converged to a wrong one, which then set the map's scale for the
// rest of the run. The neighbours of a point mostly lie on its surface, so their inverse
// distance is close to the mean of the points beside them, and their residuals widen the
// basin (docs/performance.md, "The tracker's reference dilated").

#include <map>
#include <omnidso/core/image.hpp>
#include <utility>

namespace omnidso {

// (v, u) → inverse distance; ordered row by row, the order the tracker builds its terms in.
using LevelInverseDistances = std::map<std::pair<int, int>, double>;

enum class DilationNeighbours { kDiagonal, kDirect };

// `points` with the pass's new points added; `width` × `height` is the level's image.
LevelInverseDistances dilateInverseDistances(const LevelInverseDistances& points, int width,
                                             int height, DilationNeighbours neighbours,
                                             const Mask* content = nullptr);

}  // namespace omnidso
