#include <meshfit/correspondence.h>

#include <CGAL/Orthogonal_incremental_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <numeric>

namespace meshfit {

namespace {

using Point_map = CGAL::Pointer_property_map<Point_3>::const_type;
using Traits = CGAL::Search_traits_adapter<std::size_t, Point_map, CGAL::Search_traits_3<Kernel>>;
using Search = CGAL::Orthogonal_incremental_neighbor_search<Traits>;
using Tree = Search::Tree;

// The fixed pairs (the user's) into `result`; returns the template vertices they take.
std::vector<bool> assign_fixed_pairs(const std::vector<Correspondence>& fixed, std::size_t template_size,
                                     Closest_point_assignment& result) {
  const std::size_t n = result.template_of.size();
  std::vector<bool> reserved(template_size, false);
  for (const Correspondence& c : fixed) {
    if (c.template_vertex >= template_size || c.network_vertex >= n)
      throw Invalid_input(c.where, "pair (" + std::to_string(c.template_vertex) + ", " +
                                       std::to_string(c.network_vertex) + ") is out of range");
    result.template_of[c.network_vertex] = c.template_vertex;
    reserved[c.template_vertex] = true;
  }
  return reserved;
}

// The network vertices without a template vertex, in order.
std::vector<std::size_t> unassigned_network_vertices(const Closest_point_assignment& result) {
  std::vector<std::size_t> out;
  for (std::size_t v = 0; v < result.template_of.size(); ++v)
    if (result.template_of[v] == Closest_point_assignment::unassigned) out.push_back(v);
  return out;
}

// Nearest template vertex not in `taken` of a network vertex; among equidistant ones the lowest
// index (the incremental search yields them in order of distance).
class Nearest_free {
 public:
  Nearest_free(const std::vector<Point_3>& pts, const std::vector<std::size_t>& free_vertices)
      : m_pts(pts),
        m_point_map(pts.data()),
        m_tree(free_vertices.begin(), free_vertices.end(), Tree::Splitter(), Traits(m_point_map)) {
    m_tree.build();
  }

  std::size_t operator()(const Point_3& q, const std::vector<bool>& taken) const {
    Search search(m_tree, q, 0.0, true, Search::Distance(m_point_map));
    std::size_t best = Closest_point_assignment::unassigned;
    for (auto it = search.begin(); it != search.end(); ++it) {
      if (taken[it->first]) continue;
      if (best == Closest_point_assignment::unassigned) {
        best = it->first;
        continue;
      }
      const CGAL::Comparison_result c = CGAL::compare_distance_to_point(q, m_pts[it->first], m_pts[best]);
      if (c == CGAL::LARGER) break;
      if (c == CGAL::SMALLER || it->first < best) best = it->first;  // doubles may misorder near-ties
    }
    return best;
  }

 private:
  const std::vector<Point_3>& m_pts;
  Point_map m_point_map;
  Tree m_tree;
};

// The pending network vertices that want a template vertex, grouped by the vertex they want and,
// within a group, in the order they may take it. Conflicts: feature points first, then nearer,
// then lower network index.
std::vector<std::size_t> by_precedence(const std::vector<std::size_t>& pending, const std::vector<std::size_t>& wanted,
                                       const Curve_network& network, const std::vector<Point_3>& pts) {
  std::vector<std::size_t> order;
  for (std::size_t v : pending)
    if (wanted[v] != Closest_point_assignment::unassigned) order.push_back(v);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (wanted[a] != wanted[b]) return wanted[a] < wanted[b];
    const bool fa = network.is_feature_point(a), fb = network.is_feature_point(b);
    if (fa != fb) return fa;
    const CGAL::Comparison_result c =
        CGAL::compare_distance_to_point(pts[wanted[a]], network.point(a), network.point(b));
    if (c != CGAL::EQUAL) return c == CGAL::SMALLER;
    return a < b;
  });
  return order;
}

// The first of each group of `order` (by_precedence) takes the vertex it wants; returns the
// others, the round's losers.
std::vector<std::size_t> assign_winners(const std::vector<std::size_t>& order, const std::vector<std::size_t>& wanted,
                                        std::vector<bool>& taken, Closest_point_assignment& result) {
  std::vector<std::size_t> losers;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t v = order[k];
    if (k > 0 && wanted[order[k - 1]] == wanted[v]) {
      losers.push_back(v);
    } else {
      result.template_of[v] = wanted[v];
      taken[wanted[v]] = true;
    }
  }
  return losers;
}

}  // namespace

Closest_point_assignment closest_point_correspondences(const std::vector<Point_3>& pts,
                                                       const Curve_network& network,
                                                       const std::vector<Correspondence>& fixed,
                                                       Loser_rule rule, const std::vector<bool>& candidates) {
  const std::size_t n = network.number_of_vertices();
  Closest_point_assignment result;
  result.template_of.assign(n, Closest_point_assignment::unassigned);
  const std::vector<bool> reserved = assign_fixed_pairs(fixed, pts.size(), result);

  std::vector<std::size_t> free_vertices;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (!reserved[i] && (candidates.empty() || (i < candidates.size() && candidates[i]))) free_vertices.push_back(i);
  if (free_vertices.empty()) {
    result.losers = unassigned_network_vertices(result);
    return result;
  }
  const Nearest_free nearest_free(pts, free_vertices);
  std::vector<bool> taken = reserved;
  for (std::size_t i = 0; i < candidates.size() && i < taken.size(); ++i) taken[i] = taken[i] || !candidates[i];

  std::vector<std::size_t> pending = unassigned_network_vertices(result);
  std::vector<std::size_t> wanted(n, Closest_point_assignment::unassigned);
  do {
    for (std::size_t v : pending) wanted[v] = nearest_free(network.point(v), taken);
    pending = assign_winners(by_precedence(pending, wanted, network, pts), wanted, taken, result);
  } while (rule == Loser_rule::next_nearest && !pending.empty() &&
           std::find(taken.begin(), taken.end(), false) != taken.end());
  result.losers = pending;
  std::sort(result.losers.begin(), result.losers.end());
  return result;
}

}  // namespace meshfit
