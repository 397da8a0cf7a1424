// meshfit: template-vertex ↔ network-vertex pairs (thesis §2.1), as given by the user.
#ifndef MESHFIT_CORRESPONDENCE_H
#define MESHFIT_CORRESPONDENCE_H

#include <meshfit/curve_network.h>
#include <meshfit/exceptions.h>
#include <meshfit/kernel.h>

#include <cstddef>
#include <string>
#include <vector>

namespace meshfit {

/// A template vertex paired with a network vertex.
struct Correspondence {
  std::size_t template_vertex = 0;
  std::size_t network_vertex = 0;
  Input_location where;  ///< where the pair was read from (empty when built in code)

  friend bool operator==(const Correspondence& a, const Correspondence& b) {
    return a.template_vertex == b.template_vertex && a.network_vertex == b.network_vertex;
  }
};

/// Reads pairs, one per line `i x y z` (`#` comments and blank lines ignored), where `i` is a
/// template vertex index and `(x, y, z)` a vertex of `network` within its merge tolerance.
/// \throws Invalid_input naming the file and line of a malformed line, of a point that is not a
///         network vertex, or of a pair repeating an earlier pair's template or network vertex.
std::vector<Correspondence> read_correspondences(const std::string& path, const Curve_network& network);
std::vector<Correspondence> parse_correspondences(const std::string& content, const std::string& name,
                                                  const Curve_network& network);

/// Checks pairs against a template with the given vertex positions: indices in range, at least
/// four pairs, and neither the template vertices nor the network vertices all coplanar (exact
/// test), so that an RBF with an affine term is defined by them.
/// \throws Invalid_input naming the pair (its line when known) or the set.
void validate_correspondences(const std::vector<Correspondence>& pairs,
                              const std::vector<Point_3>& template_points,
                              const Curve_network& network);

/// Writes pairs in the format read_correspondences reads.
void write_correspondences(const std::string& path, const std::vector<Correspondence>& pairs,
                           const Curve_network& network);

}  // namespace meshfit

#endif  // MESHFIT_CORRESPONDENCE_H
