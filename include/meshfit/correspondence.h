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
  std::size_t template_vertex = 0;  ///< index of the template vertex, in the order of the template file
  std::size_t network_vertex = 0;   ///< index of the network vertex (Curve_network's numbering)
  Input_location where;  ///< where the pair was read from (empty when built in code)

  /// Same template vertex and same network vertex (`where` is not compared).
  friend bool operator==(const Correspondence& a, const Correspondence& b) {
    return a.template_vertex == b.template_vertex && a.network_vertex == b.network_vertex;
  }
};

/// Reads pairs, one per line `i x y z` (`#` comments and blank lines ignored), where `i` is a
/// template vertex index and `(x, y, z)` a vertex of `network` within its merge tolerance; or
/// `i @k`, where `k` is the index of a network vertex (0-based, in order of first appearance in
/// the curve file, after merging: Curve_network's numbering). Both forms may be mixed.
/// \throws Invalid_input naming the file and line of a malformed line, of a point that is not a
///         network vertex, of an index `@k` with no network vertex, or of a pair repeating an earlier pair's template or network vertex.
std::vector<Correspondence> read_correspondences(const std::string& path, const Curve_network& network);
/// Same as read_correspondences, from the content of a file; `name` is used in error messages.
std::vector<Correspondence> parse_correspondences(const std::string& content, const std::string& name,
                                                  const Curve_network& network);

/// Checks pairs against a template with the given vertex positions: indices in range, at least
/// four pairs, and neither the template vertices nor the network vertices all coplanar (exact
/// test), so that an RBF with an affine term is defined by them. With `allow_coplanar_template`
/// (what deformation needs: it adds auxiliary pairs off the plane) the template vertices may be
/// coplanar but not collinear.
/// \throws Invalid_input naming the pair (its line when known) or the set (its file when known).
void validate_correspondences(const std::vector<Correspondence>& pairs,
                              const std::vector<Point_3>& template_points,
                              const Curve_network& network, bool allow_coplanar_template = false);

/// The closest-point correspondences of thesis §2.1.
struct Closest_point_assignment {
  /// The value of template_of for a network vertex without a template vertex.
  static constexpr std::size_t unassigned = static_cast<std::size_t>(-1);
  /// For each network vertex, its template vertex, or `unassigned`.
  std::vector<std::size_t> template_of;
  /// Network vertices that lost their nearest template vertex to another one (sorted).
  std::vector<std::size_t> losers;
};

/// What happens to a network vertex that loses its nearest template vertex to another.
enum class Loser_rule {
  drop,          ///< it stays unassigned (the thesis)
  next_nearest   ///< it competes again for its nearest template vertex not yet taken
};

/// Pairs every network vertex with its nearest template vertex (a k-d tree: O(n log m)).
/// `fixed` pairs (the user's) are kept as they are and their template vertices are taken by no
/// one else. When several network vertices want the same template vertex, the winner is decided
/// by, in order: a feature point beats a non-feature point; the nearer wins (exact distance
/// comparison); the lower network index wins. Losers stay unassigned and are listed, or, with
/// Loser_rule::next_nearest, compete again (same rules) for their nearest vertex not yet taken
/// until every one has a vertex or none is left. Equidistant template vertices are resolved by
/// the lower template index. When `candidates` is given (one flag per template point), only the
/// flagged points are paired (the template's unused vertices are not).
/// \throws Invalid_input when a fixed pair's indices are out of range.
Closest_point_assignment closest_point_correspondences(const std::vector<Point_3>& template_points,
                                                       const Curve_network& network,
                                                       const std::vector<Correspondence>& fixed = {},
                                                       Loser_rule rule = Loser_rule::drop,
                                                       const std::vector<bool>& candidates = {});

/// Writes pairs in the format read_correspondences reads.
void write_correspondences(const std::string& path, const std::vector<Correspondence>& pairs,
                           const Curve_network& network);

}  // namespace meshfit

#endif  // MESHFIT_CORRESPONDENCE_H
