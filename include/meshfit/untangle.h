// meshfit: untangling a patch of a triangle mesh with a foldover-free energy (Garanzha, Kaporin,
// Kudryavtseva, Protais, Ray and Sokolov 2021, "Foldover-free maps in 50 lines of code").
//
// Each face is seen in the plane orthogonal to its reference normal, where its Jacobian J maps an
// equilateral reference triangle onto its projection. The energy of a face is
//     (1 - θ) tr(JᵀJ) / χ(det J, ε) + θ (1 + det² J) / χ(det J, ε),   χ(D, ε) = (D + √(ε² + D²)) / 2,
// finite for every J (χ > 0) and, as ε goes to 0, infinite on inverted faces: minimising it with ε
// decreasing as the paper prescribes drives every face to positive orientation where a
// foldover-free placement of the free vertices exists, and then keeps the faces well shaped. The
// free vertices move in the plane through their position orthogonal to their own normal (two
// degrees of freedom each), so the patch keeps its place on the surface; a fairness term,
// `fairness` times the squared distance of each free vertex from its neighbours' mean (in units
// of the patch's mean edge length), spreads them evenly where the faces alone would not care.
// The minimiser is L-BFGS (LBFGS++, Debian's liblbfgspp-dev).
//
// The function is a placement proposal: the caller judges the result with its exact predicates.
#ifndef MESHFIT_UNTANGLE_H
#define MESHFIT_UNTANGLE_H

#include <meshfit/kernel.h>

#include <array>
#include <cstddef>
#include <vector>

namespace meshfit {

/// What an untangling did. Orientations here are in floating point (the caller's exact
/// predicates decide).
struct Untangle_report {
  std::size_t free_vertices = 0;  ///< vertices that could move
  std::size_t faces = 0;          ///< faces with a free corner (the others are left out)
  std::size_t outer_iterations = 0;  ///< decreases of ε (the work is bounded: about 8e6 face evaluations)
  std::size_t inverted_before = 0;   ///< faces not positively oriented before
  std::size_t inverted_after = 0;    ///< and after
};

/// Moves the free vertices among `positions` so that each of `faces` is positively oriented in the
/// plane orthogonal to `face_normal[f]` (see the top of this file); a vertex `i` with `free[i]`
/// moves in the plane orthogonal to `vertex_normal[i]`. Faces with no free corner are left out; a
/// free vertex's neighbours are the other corners of its faces. Returns every vertex's new
/// position (those not free unchanged).
/// \throws Invalid_input when the sizes differ, a corner is out of range, a normal of a free
///         vertex or of a face with a free corner is zero, or `fairness` is negative or not finite.
std::vector<Point_3> untangle_faces(const std::vector<Point_3>& positions,
                                    const std::vector<std::array<std::size_t, 3>>& faces,
                                    const std::vector<Vector_3>& face_normal, const std::vector<bool>& free,
                                    const std::vector<Vector_3>& vertex_normal, double fairness = 1.0,
                                    Untangle_report* report = nullptr);

}  // namespace meshfit

#endif  // MESHFIT_UNTANGLE_H
