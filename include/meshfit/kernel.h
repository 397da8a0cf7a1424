// meshfit: the geometric kernel. Predicates are exact, constructions are not (Epick): every
// geometric decision in meshfit is an exact predicate on existing points.
#ifndef MESHFIT_KERNEL_H
#define MESHFIT_KERNEL_H

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace meshfit {

/// CGAL's kernel with exact predicates and inexact constructions (Epick).
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point_3 = Kernel::Point_3;      ///< a point of Kernel
using Vector_3 = Kernel::Vector_3;    ///< a vector of Kernel
using Segment_3 = Kernel::Segment_3;  ///< a segment of Kernel
using Bbox_3 = CGAL::Bbox_3;          ///< an axis-aligned box (double coordinates)

}  // namespace meshfit

#endif  // MESHFIT_KERNEL_H
