// meshfit internal: cutting a network's long segments into pieces of about a given length.
#ifndef MESHFIT_INTERNAL_RESAMPLE_NETWORK_H
#define MESHFIT_INTERNAL_RESAMPLE_NETWORK_H

#include <meshfit/curve_network.h>

#include <cstddef>
#include <vector>

namespace meshfit {
namespace internal {

/// A network whose long segments are cut, and how it maps onto the original one.
struct Resampled_network {
  Curve_network network;                ///< the original's polylines, in order, with points added
  std::size_t added = 0;                ///< points added (0: `network` is a copy of the original)
  std::vector<std::size_t> vertex_of;   ///< original vertex → its index in `network`
  std::vector<std::size_t> segment_of;  ///< segment of `network` → the original segment it is part of
};

/// Every segment longer than 2 `spacing` is cut into ceil(length / spacing) equal pieces, but for
/// those with `whole[k]` (when `whole` is not empty); the added points lie on the segment (within
/// rounding). Polylines keep their order, so polyline
/// numbers in messages still name the user's. When an added point would merge with a network
/// vertex (curves passing within the merge tolerance), or round onto a neighbour, nothing is cut.
Resampled_network resample_long_segments(const Curve_network& network, double spacing,
                                         const std::vector<bool>& whole = {});

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_RESAMPLE_NETWORK_H
