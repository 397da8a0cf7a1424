// meshfit: detecting faces that a deformation flips (thesis §2.3.1).
//
// A triangle p1 p2 p3 moves to q1 q2 q3. Everything is judged in the plane Π of the triangle
// before the motion, with the moved vertices projected onto Π (thesis fig. 2.9). Orientation in Π
// of projected points is the sign of n · ((b − a) × (c − a)) with n = (p2 − p1) × (p3 − p1):
// projecting adds multiples of n, which this expression ignores, so no point is constructed and
// the sign is computed exactly (interval filter, then exact arithmetic).
#ifndef MESHFIT_FLIP_H
#define MESHFIT_FLIP_H

#include <meshfit/kernel.h>
#include <meshfit/predicates.h>

#include <boost/graph/graph_traits.hpp>

#include <array>
#include <cmath>

namespace meshfit {

/// What a motion did to a triangle's orientation.
enum class Flip_state {
  kept,        ///< same orientation in Π before and after
  flipped,     ///< reversed orientation
  degenerate   ///< the moved triangle projects to a segment or a point (or the original is
               ///< degenerate, so Π is undefined)
};

/// The result of the flip counter.
struct Flip_count {
  int crossings = 0;         ///< motions t_i that crossed the opposite edge line d_i
  bool degenerate = false;   ///< a motion ended exactly on the line, or the face had no plane
  /// degenerate, or flipped when the number of crossings is odd, else kept.
  Flip_state state() const {
    return degenerate ? Flip_state::degenerate : (crossings % 2 ? Flip_state::flipped : Flip_state::kept);
  }
};

/// The flip counter (thesis §2.3.1.2): for each vertex in turn, does its motion t_i cross the line
/// of the opposite edge d_i in Π; an odd count means the face flipped. The thesis tests all three
/// motions against the edges of the face before the motion, which miscounts when all vertices
/// move (a pure translation can carry one vertex across its opposite edge line); here the vertices
/// move one after the other and each motion is tested against the opposite edge as it then
/// stands, which makes the parity of the count exactly the change of orientation. Every test is
/// an exact predicate.
Flip_count flip_counter(const Triangle_points& before, const Triangle_points& after);

/// The exact orientation test the counter must agree with: the sign of the moved triangle's
/// orientation in Π.
Flip_state orientation_flip_test(const Triangle_points& before, const Triangle_points& after);

/// The common baseline (thesis §2.3.1.1, case 2): flipped when the angle between the face normals
/// before and after exceeds `max_angle` (radians). Constructs the normals in floating point; a
/// degenerate triangle (zero normal) is reported as degenerate.
Flip_state normal_angle_flip_test(const Triangle_points& before, const Triangle_points& after,
                                  double max_angle);

}  // namespace meshfit

#endif  // MESHFIT_FLIP_H
