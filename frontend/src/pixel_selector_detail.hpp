#pragma once
// Internal steps of candidate selection (pixel_selector.cc), in their own file because each
// replaces a simpler formulation with a faster one that must give the same bits
// (tests/frontend/pixel_selector_test.cc compares the selection with the simple one).
#include <cstdint>
#include <omnidso/core/image.hpp>
#include <vector>

namespace omnidso::detail {

// 255 where a pattern of radius `radius` fits: inside the image border and, with a mask, the
// centre and the outline of the (2r+1)² square around it valid. Empty mask = all valid.
Mask usableMask(const Mask& mask, int width, int height, int radius);

// The k-th smallest of `values` (0-based), bit for bit what std::nth_element puts at k.
// `values` may be reordered; `keys` is scratch kept by the caller across calls.
float kthSmallest(std::vector<float>& values, size_t k, std::vector<std::uint32_t>& keys);

}  // namespace omnidso::detail
