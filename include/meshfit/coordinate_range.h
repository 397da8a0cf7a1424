// meshfit: the range of coordinates meshfit supports, checked once where inputs enter (the readers
// and the library's entry points), so that no predicate or construction ever sees a non-finite
// number.
//
// Supported: every coordinate finite with |x| <= max_coordinate (1e100), and the bounding-box
// diagonal of each input (template, curve network) at least min_extent (1e-100). Within that
// range squared lengths and the products of the exact predicates stay far from overflow, and
// fit_template_to_curves and deform_template work on copies scaled by a power of two (exact) to a
// unit-sized box, so their results do not depend on the unit of the inputs.
#ifndef MESHFIT_COORDINATE_RANGE_H
#define MESHFIT_COORDINATE_RANGE_H

#include <meshfit/exceptions.h>
#include <meshfit/kernel.h>

#include <cmath>
#include <string>

namespace meshfit {

constexpr double max_coordinate = 1e100;  ///< largest |x| of any input coordinate
constexpr double min_extent = 1e-100;     ///< smallest bounding-box diagonal of an input

/// \throws Invalid_input at `where`, naming `element` ("vertex 12"), when a coordinate of `p` is
///         not finite or larger than max_coordinate in magnitude.
void check_coordinate_range(const Point_3& p, const Input_location& where, const std::string& element);

/// Whether every coordinate of `p` is finite and at most max_coordinate in magnitude: what
/// check_coordinate_range checks, for callers that build the element's name only when it fails
/// (rather than once for each of millions of points).
inline bool in_coordinate_range(const Point_3& p) {
  return std::abs(p.x()) <= max_coordinate && std::abs(p.y()) <= max_coordinate && std::abs(p.z()) <= max_coordinate;
}

/// The diagonal of `box`, computed without squaring its sides themselves (no underflow at 1e-200
/// nor overflow at 1e200); 0 for an empty or one-point box.
double bbox_diagonal(const Bbox_3& box);

/// Returns the diagonal of `box` (the bounding box of the points of `what`).
/// \throws Invalid_input at `where`, naming `what` ("the template"), when the diagonal is zero
///         (all points coincide) or below min_extent.
double check_extent(const Bbox_3& box, const Input_location& where, const std::string& what);

}  // namespace meshfit

#endif  // MESHFIT_COORDINATE_RANGE_H
