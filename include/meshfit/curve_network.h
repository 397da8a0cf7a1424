// meshfit: the curve network (thesis §1.2): piecewise-linear polylines whose coincident points are
// merged into network vertices. A network vertex with more than two incident segments is a
// feature point.
#ifndef MESHFIT_CURVE_NETWORK_H
#define MESHFIT_CURVE_NETWORK_H

#include <meshfit/exceptions.h>
#include <meshfit/kernel.h>

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace meshfit {

/// The default merge tolerance, relative to the diagonal of the network's bounding box.
constexpr double default_merge_tolerance = 1e-9;

class Curve_network;
namespace internal {
Curve_network scaled(const Curve_network& network, double s);  // (internal/unit_scale.h)
}

/// A network of polylines. Points closer than `tolerance()` (the relative merge tolerance times
/// the bounding-box diagonal) are one network vertex: the first point seen (in file order) is the
/// vertex's position and later points within the tolerance of it are merged into it. Segments
/// are unique: a segment given twice (in either direction) is stored once.
class Curve_network {
 public:
  using Polyline = std::vector<Point_3>;        ///< an input polyline: its points in order
  using Segment = std::array<std::size_t, 2>;  ///< a segment: its two network vertices

  /// A maximal chain of segments whose inner vertices have degree 2: it runs between feature
  /// points or endpoints, or is a closed loop.
  struct Curve {
    std::vector<std::size_t> vertices;  ///< consecutive network vertices
    bool closed = false;                ///< first and last vertex are the same
  };

  Curve_network() = default;
  /// Builds the network. `where`, when given, has one location per polyline and is used in error
  /// messages. \throws Invalid_input for a polyline of fewer than two points, a non-finite
  /// coordinate, a segment of zero length after merging, or a network whose points all coincide.
  explicit Curve_network(const std::vector<Polyline>& polylines,
                         double relative_tolerance = default_merge_tolerance,
                         const std::vector<Input_location>& where = {});

  /// Network vertices, after merging.
  std::size_t number_of_vertices() const { return m_points.size(); }
  /// Distinct segments.
  std::size_t number_of_segments() const { return m_segments.size(); }
  /// The position of every network vertex, in order of first appearance.
  const std::vector<Point_3>& points() const { return m_points; }
  /// The position of vertex `v`. \throws std::out_of_range when there is no vertex `v`.
  const Point_3& point(std::size_t v) const { return m_points.at(v); }
  /// Every segment, in order of first appearance.
  const std::vector<Segment>& segments() const { return m_segments; }
  /// A view of consecutive segment indices (valid while the network lives).
  struct Index_range {
    const std::size_t* first = nullptr;  ///< the first index
    const std::size_t* last = nullptr;   ///< one past the last
    const std::size_t* begin() const { return first; }  ///< for range-for
    const std::size_t* end() const { return last; }     ///< for range-for
    std::size_t size() const { return static_cast<std::size_t>(last - first); }  ///< how many
    bool empty() const { return first == last; }                                ///< none
    std::size_t operator[](std::size_t i) const { return first[i]; }            ///< the i-th (unchecked)
  };
  /// Indices of the segments incident to vertex `v`, in increasing order.
  /// \throws std::out_of_range when there is no vertex `v`.
  Index_range incident_segments(std::size_t v) const {
    if (v >= number_of_vertices()) throw std::out_of_range("Curve_network: no vertex " + std::to_string(v));
    return {m_incident.data() + m_incident_offsets[v], m_incident.data() + m_incident_offsets[v + 1]};
  }
  /// The number of segments incident to vertex `v`.
  std::size_t degree(std::size_t v) const { return incident_segments(v).size(); }
  /// More than two segments meet at `v`.
  bool is_feature_point(std::size_t v) const { return degree(v) > 2; }
  /// Exactly one segment ends at `v`.
  bool is_endpoint(std::size_t v) const { return degree(v) == 1; }
  /// The feature points, in increasing order.
  std::vector<std::size_t> feature_points() const;
  /// The endpoints, in increasing order.
  std::vector<std::size_t> endpoints() const;

  /// The input polylines as network vertex indices, in input order.
  const std::vector<std::vector<std::size_t>>& polylines() const { return m_polylines; }
  /// Input polylines that return to their first vertex.
  std::size_t number_of_closed_polylines() const;
  /// Maximal chains between feature points and endpoints (see Curve), in a deterministic order.
  const std::vector<Curve>& curves() const { return m_curves; }
  /// Number of independent cycles of the network graph (segments − vertices + components).
  std::size_t number_of_independent_cycles() const;

  /// Connected components of the network graph.
  std::size_t number_of_components() const { return m_number_of_components; }
  /// Empty when the network graph is planar (it can be drawn on a sphere or a disc without
  /// crossings); else the segments of a Kuratowski subgraph (a subdivision of K5 or K3,3) that
  /// proves it is not (Boyer–Myrvold, Boost.Graph).
  std::vector<std::size_t> non_planar_segments() const;
  /// The input polylines (0-based, in input order) that contain any of `segments`.
  std::vector<std::size_t> polylines_of_segments(const std::vector<std::size_t>& segments) const;
  /// Component of vertex `v`, numbered from 0 in order of their lowest vertex.
  std::size_t component(std::size_t v) const { return m_component.at(v); }

  /// The bounding box of the network's points.
  const Bbox_3& bbox() const { return m_bbox; }
  /// Absolute merge tolerance (relative tolerance × bounding-box diagonal).
  double tolerance() const { return m_tolerance; }
  /// The merge tolerance relative to the bounding-box diagonal, as given to the constructor.
  double relative_tolerance() const { return m_relative_tolerance; }
  /// Segments given more than once in the input (they are stored once).
  std::size_t number_of_repeated_segments() const { return m_repeated_segments; }

  /// The network vertex within `tolerance()` of `p`, if any (the nearest one when several are).
  std::optional<std::size_t> find_vertex(const Point_3& p) const;

 private:
  friend Curve_network internal::scaled(const Curve_network& network, double s);
  std::vector<Point_3> m_points;
  std::vector<Segment> m_segments;
  // The segments incident to each vertex, in compressed rows (vertex v's are
  // m_incident[m_incident_offsets[v] .. m_incident_offsets[v + 1]]): one array rather than a
  // vector per vertex, which took 57 bytes a vertex of the 260 that reading a long polyline
  // needed.
  std::vector<std::size_t> m_incident_offsets{0};
  std::vector<std::size_t> m_incident;
  std::vector<std::vector<std::size_t>> m_polylines;
  std::vector<Curve> m_curves;
  std::vector<std::size_t> m_component;
  std::size_t m_number_of_components = 0;
  std::size_t m_repeated_segments = 0;
  Bbox_3 m_bbox;
  double m_tolerance = 0;
  double m_relative_tolerance = 0;
  // The vertices by grid cell of side twice `tolerance()`, sorted by cell then vertex: a point's
  // merge partners lie in its own cell or the neighbours on its near side (find_vertex).
  struct Cell_entry {
    std::array<long long, 3> cell;
    std::size_t item;
  };
  std::vector<Cell_entry> m_cells;
  std::array<long long, 3> cell_of(const Point_3& p) const;
  // The constructor's steps, in the order it takes them (curve_network.cpp).
  class Point_merger;
  void merge_points(const std::vector<Polyline>& polylines);
  void make_segments(const std::vector<Input_location>& where);
  void make_incidences();
  void number_components();
  void trace_curves();
  template <typename Visit>
  void visit_near(const std::vector<Cell_entry>& grid, const Point_3& p, const Visit& visit) const;
};

/// Reads a network in CGAL's polyline format: one polyline per line, `N x1 y1 z1 … xN yN zN`;
/// blank lines and lines starting with `#` are ignored; a closed curve repeats its first point.
/// A path ending in `.obj` or `.ply` (any case) is read as a mesh file instead, and its curve
/// edges are the network (faces are ignored): OBJ `l` lines (each consecutive pair of vertices a
/// segment) and PLY `edge` instances whose integer property `curve` is nonzero (what meshfit
/// writes with `Write_options::curves_in_mesh`). Network vertices are numbered in order of first
/// appearance (points for polylines, edge ends for mesh files), after merging.
/// \throws Invalid_input naming the file and line (or byte offset) for any malformed line, and
///         the file for a mesh file without curve edges.
Curve_network read_curve_network(const std::string& path,
                                 double relative_tolerance = default_merge_tolerance);
/// Same, from the content of a file; `name` is used in error messages.
Curve_network parse_curve_network(const std::string& content, const std::string& name,
                                  double relative_tolerance = default_merge_tolerance);

/// Writes a network as polylines, one per curve of `network.curves()`.
void write_curve_network(const std::string& path, const Curve_network& network);

}  // namespace meshfit

#endif  // MESHFIT_CURVE_NETWORK_H
