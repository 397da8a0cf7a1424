#include <meshfit/curve_network.h>

#include <meshfit/coordinate_range.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/internal/resample_network.h>
#include <boost/pending/disjoint_sets.hpp>

#include "io/polygon_soup.h"
#include "io/text_parser.h"
#include "io/write_file.h"

#include <boost/graph/adjacency_list.hpp>
// Boost's planarity test trips GCC 12's -Wmaybe-uninitialized inside its own headers
// (bicomp_root, previous_vertex in extract_kuratowski_subgraph), for the whole file; popped at its
// end, so that the files compiled after it in a unity build (MESHFIT_UNITY_BUILD) keep the warning.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/boyer_myrvold_planar_test.hpp>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <numeric>
#include <tuple>
#include <ostream>

namespace meshfit {

namespace {
Input_location location_of(const std::vector<Input_location>& where, std::size_t k) {
  return k < where.size() ? where[k] : Input_location{};
}
// Numbered from 1 in input order, as its points are and as the stages name polylines ("polyline 5
// (in file order)"); the message's location, when given, has the line.
std::string polyline_name(std::size_t k) { return "polyline " + std::to_string(k + 1); }
}  // namespace

namespace {
using Cell = std::array<long long, 3>;
bool cell_less(const Cell& a, const Cell& b) { return std::tie(a[0], a[1], a[2]) < std::tie(b[0], b[1], b[2]); }
// p's position in the merge grid: cells of side twice the tolerance from the box's corner.
std::array<double, 3> grid_coordinates(const Point_3& p, const Bbox_3& box, double tolerance) {
  const double side = 2 * tolerance;
  return {(p.x() - box.xmin()) / side, (p.y() - box.ymin()) / side, (p.z() - box.zmin()) / side};
}
Cell cell_at(const std::array<double, 3>& q) {
  return {static_cast<long long>(std::floor(q[0])), static_cast<long long>(std::floor(q[1])),
          static_cast<long long>(std::floor(q[2]))};
}
// The cells (lo … hi in each coordinate) that may hold points within the tolerance of a point at
// grid coordinates q: its own and the neighbour on the side it is nearer to, or both neighbours
// when it is about halfway.
void near_cells(const std::array<double, 3>& q, Cell& lo, Cell& hi) {
  const Cell c = cell_at(q);
  for (int i = 0; i < 3; ++i) {
    const double f = q[i] - static_cast<double>(c[i]);
    lo[i] = c[i] - (f < 0.501 ? 1 : 0);
    hi[i] = c[i] + (f > 0.499 ? 1 : 0);
  }
}
}  // namespace

std::array<long long, 3> Curve_network::cell_of(const Point_3& p) const {
  return cell_at(grid_coordinates(p, m_bbox, m_tolerance));
}

// Calls visit(item) for every entry of `grid` (sorted by cell) in the cells near p (near_cells).
// Entries of one column (x, y) are contiguous in z.
template <typename Visit>
void Curve_network::visit_near(const std::vector<Cell_entry>& grid, const Point_3& p, const Visit& visit) const {
  Cell lo, hi;
  near_cells(grid_coordinates(p, m_bbox, m_tolerance), lo, hi);
  const auto less = [](const Cell_entry& e, const Cell& k) { return cell_less(e.cell, k); };
  for (long long x = lo[0]; x <= hi[0]; ++x)
    for (long long y = lo[1]; y <= hi[1]; ++y) {
      auto it = std::lower_bound(grid.begin(), grid.end(), Cell{x, y, lo[2]}, less);
      for (; it != grid.end() && it->cell[0] == x && it->cell[1] == y && it->cell[2] <= hi[2]; ++it) visit(it->item);
    }
}

std::optional<std::size_t> Curve_network::find_vertex(const Point_3& p) const {
  if (m_points.empty() || !std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
    return std::nullopt;
  // A point far outside the box cannot be a vertex (and its cell index could overflow).
  const double t = m_tolerance;
  if (p.x() < m_bbox.xmin() - t || p.x() > m_bbox.xmax() + t || p.y() < m_bbox.ymin() - t ||
      p.y() > m_bbox.ymax() + t || p.z() < m_bbox.zmin() - t || p.z() > m_bbox.zmax() + t)
    return std::nullopt;
  std::optional<std::size_t> best;
  double best_d2 = t * t;
  visit_near(m_cells, p, [&](std::size_t v) {
    const double d2 = CGAL::squared_distance(p, m_points[v]);
    if (d2 < best_d2 || (d2 == best_d2 && (!best || v < *best))) {
      best_d2 = d2;
      best = v;
    }
  });
  return best;
}

namespace {
void check_merge_tolerance(double relative_tolerance) {
  if (!(relative_tolerance >= 1e-15 && relative_tolerance <= 1e-2))
    throw Invalid_input("the merge tolerance must be between 1e-15 and 1e-2 of the bounding-box "
                        "diagonal, not " + internal::format_number(relative_tolerance));
}

// The box of every point, after checking that each polyline has 2 points or more and that every
// point's coordinates are in range.
Bbox_3 checked_bbox(const std::vector<Curve_network::Polyline>& polylines, const std::vector<Input_location>& where) {
  Bbox_3 box;
  bool any = false;
  for (std::size_t k = 0; k < polylines.size(); ++k) {
    if (polylines[k].size() < 2)
      throw Invalid_input(location_of(where, k),
                          polyline_name(k) + " has " + std::to_string(polylines[k].size()) +
                              " point(s); a polyline needs at least 2");
    for (const Point_3& p : polylines[k]) {
      if (!in_coordinate_range(p))
        check_coordinate_range(p, location_of(where, k),
                               polyline_name(k) + ", point " + std::to_string(&p - polylines[k].data() + 1));
      box += p.bbox();
      any = true;
    }
  }
  if (!any) throw Invalid_input("the curve network is empty");
  return box;
}

// For each segment of the polylines in input order, whether an earlier one joins the same two
// vertices.
std::vector<bool> repeated_segments(const std::vector<std::vector<std::size_t>>& polylines) {
  std::vector<std::array<std::size_t, 3>> keyed;  // (lower end, upper end, position in input order)
  for (const auto& ids : polylines)
    for (std::size_t i = 0; i + 1 < ids.size(); ++i)
      keyed.push_back({std::min(ids[i], ids[i + 1]), std::max(ids[i], ids[i + 1]), keyed.size()});
  std::sort(keyed.begin(), keyed.end());
  std::vector<bool> repeated(keyed.size(), false);
  for (std::size_t i = 1; i < keyed.size(); ++i)
    if (keyed[i][0] == keyed[i - 1][0] && keyed[i][1] == keyed[i - 1][1]) repeated[keyed[i][2]] = true;
  return repeated;
}
}  // namespace

Curve_network::Curve_network(const std::vector<Polyline>& polylines, double relative_tolerance,
                             const std::vector<Input_location>& where) {
  check_merge_tolerance(relative_tolerance);
  m_bbox = checked_bbox(polylines, where);
  const double diagonal = check_extent(m_bbox, Input_location{}, "the curve network");
  m_relative_tolerance = relative_tolerance;
  m_tolerance = relative_tolerance * diagonal;
  merge_points(polylines);
  make_segments(where);
  make_incidences();
  number_components();
  trace_curves();
}

// Merge points: each point joins the nearest vertex within the tolerance made by an earlier point
// (the lowest such vertex when several are nearest), else becomes a vertex: the result of taking
// the points one by one in input order. The grid holds every point (by its position in input
// order), sorted once; a point that joined a vertex is skipped from then on (`m_skip`, path-halving
// pointers to the next entry still to be looked at), and the later points of a cell are jumped
// over, so that many points at one place (a feature point of high degree) cost no more than one.
class Curve_network::Point_merger {
 public:
  static constexpr std::size_t none = SIZE_MAX;

  Point_merger(const Curve_network& network, const std::vector<Polyline>& polylines)
      : m_network(network), m_t2(network.m_tolerance * network.m_tolerance) {
    std::size_t total = 0;
    for (const auto& line : polylines) total += line.size();
    m_all.reserve(total);
    for (std::size_t k = 0, g = 0; k < polylines.size(); ++k)
      for (const Point_3& p : polylines[k]) m_all.push_back({network.cell_of(p), g++});
    std::sort(m_all.begin(), m_all.end(), [](const Cell_entry& a, const Cell_entry& b) {
      return cell_less(a.cell, b.cell) || (a.cell == b.cell && a.item < b.item);
    });
    m_vertex_made_by.assign(total, none);
    m_entry_of.resize(total);
    m_skip.resize(total + 1);
    for (std::size_t i = 0; i < total; ++i) m_entry_of[m_all[i].item] = i;
    std::iota(m_skip.begin(), m_skip.end(), 0);
  }

  // The vertex point g (in input order), at p, joins: the nearest one within the tolerance made
  // by an earlier point, the lowest when several are; `none` when there is none.
  std::size_t vertex_near(const Point_3& p, std::size_t g) {
    std::size_t best = none;
    double best_d2 = m_t2;
    Cell lo, hi;
    near_cells(grid_coordinates(p, m_network.m_bbox, m_network.m_tolerance), lo, hi);
    for (long long x = lo[0]; x <= hi[0]; ++x)
      for (long long y = lo[1]; y <= hi[1]; ++y) visit_column(x, y, lo[2], hi[2], p, g, best, best_d2);
    return best;
  }

  // Point g made vertex v.
  void made_vertex(std::size_t g, std::size_t v) { m_vertex_made_by[g] = v; }
  // Point g joined a vertex: its entry is skipped from now on.
  void joined(std::size_t g) { m_skip[m_entry_of[g]] = m_entry_of[g] + 1; }

  // The vertices' grid: the entries of the points that made them, in the same order.
  std::vector<Cell_entry> vertex_cells() {
    std::vector<std::size_t>().swap(m_entry_of);
    std::vector<std::size_t>().swap(m_skip);
    std::vector<Cell_entry> cells;
    for (const Cell_entry& e : m_all)
      if (m_vertex_made_by[e.item] != none) cells.push_back({e.cell, m_vertex_made_by[e.item]});
    cells.shrink_to_fit();
    return cells;
  }

 private:
  // The first entry at or after i not skipped.
  std::size_t next_entry(std::size_t i) {
    while (m_skip[i] != i) i = m_skip[i] = m_skip[m_skip[i]];
    return i;
  }

  // The first entry not skipped at or after the first whose cell is not below `c`, from `from` on.
  std::size_t first_entry(const Cell& c, std::size_t from) {
    const auto less = [](const Cell_entry& e, const Cell& k) { return cell_less(e.cell, k); };
    return next_entry(static_cast<std::size_t>(
        std::lower_bound(m_all.begin() + static_cast<std::ptrdiff_t>(from), m_all.end(), c, less) - m_all.begin()));
  }

  // Offers p the vertices made by the earlier points of column (x, y), cells z_lo … z_hi.
  void visit_column(long long x, long long y, long long z_lo, long long z_hi, const Point_3& p, std::size_t g,
                    std::size_t& best, double& best_d2) {
    std::size_t i = first_entry(Cell{x, y, z_lo}, 0);
    while (i < m_all.size() && m_all[i].cell[0] == x && m_all[i].cell[1] == y && m_all[i].cell[2] <= z_hi) {
      if (m_all[i].item >= g) {  // this cell's later points: on to the next cell
        i = first_entry(Cell{x, y, m_all[i].cell[2] + 1}, i);
        continue;
      }
      const std::size_t v = m_vertex_made_by[m_all[i].item];  // an earlier point not skipped made one
      const double d2 = CGAL::squared_distance(p, m_network.m_points[v]);
      if (d2 < best_d2 || (d2 == best_d2 && (best == none || v < best))) best_d2 = d2, best = v;
      i = next_entry(i + 1);
    }
  }

  const Curve_network& m_network;
  const double m_t2;
  std::vector<Cell_entry> m_all;
  std::vector<std::size_t> m_vertex_made_by;  // point -> the vertex it made, if it made one
  std::vector<std::size_t> m_entry_of, m_skip;  // point -> its entry in `m_all`
};

void Curve_network::merge_points(const std::vector<Polyline>& polylines) {
  Point_merger merger(*this, polylines);
  for (std::size_t k = 0, g = 0; k < polylines.size(); ++k) {
    std::vector<std::size_t> ids;
    ids.reserve(polylines[k].size());
    for (const Point_3& p : polylines[k]) {
      std::size_t best = merger.vertex_near(p, g);
      if (best == Point_merger::none) {
        best = m_points.size();
        merger.made_vertex(g, best);
        m_points.push_back(p);
      } else {
        merger.joined(g);
      }
      ids.push_back(best);
      ++g;
    }
    m_polylines.push_back(std::move(ids));
  }
  m_cells = merger.vertex_cells();
}

// Unique segments, in order of first appearance.
void Curve_network::make_segments(const std::vector<Input_location>& where) {
  for (std::size_t k = 0; k < m_polylines.size(); ++k) {
    const auto& ids = m_polylines[k];
    for (std::size_t i = 0; i + 1 < ids.size(); ++i)
      if (ids[i] == ids[i + 1])
        throw Invalid_input(location_of(where, k),
                            polyline_name(k) + ": points " + std::to_string(i + 1) + " and " +
                                std::to_string(i + 2) + " coincide (a segment of zero length)");
  }
  const std::vector<bool> repeated = repeated_segments(m_polylines);
  std::size_t position = 0;
  for (const auto& ids : m_polylines)
    for (std::size_t i = 0; i + 1 < ids.size(); ++i) {
      if (repeated[position++]) {
        ++m_repeated_segments;
        continue;
      }
      m_segments.push_back({ids[i], ids[i + 1]});
    }
  m_segments.shrink_to_fit();
}

// Incidences in compressed rows: count, sum, fill (in segment order, so each row is sorted).
void Curve_network::make_incidences() {
  m_incident_offsets.assign(m_points.size() + 1, 0);
  for (const Segment& s : m_segments) ++m_incident_offsets[s[0] + 1], ++m_incident_offsets[s[1] + 1];
  std::partial_sum(m_incident_offsets.begin(), m_incident_offsets.end(), m_incident_offsets.begin());
  m_incident.resize(2 * m_segments.size());
  std::vector<std::size_t> fill(m_incident_offsets.begin(), m_incident_offsets.end() - 1);
  for (std::size_t k = 0; k < m_segments.size(); ++k)
    for (std::size_t v : m_segments[k]) m_incident[fill[v]++] = k;
}

// Components (union-find over segments), numbered by their lowest vertex.
void Curve_network::number_components() {
  boost::disjoint_sets_with_storage<> sets(m_points.size());
  auto root = [&](std::size_t i) { return sets.find_set(i); };
  for (const Segment& s : m_segments) sets.union_set(s[0], s[1]);
  m_component.assign(m_points.size(), 0);
  std::vector<std::size_t> number(m_points.size(), SIZE_MAX);
  for (std::size_t v = 0; v < m_points.size(); ++v) {
    const std::size_t r = root(v);
    if (number[r] == SIZE_MAX) number[r] = m_number_of_components++;
    m_component[v] = number[r];
  }
}

// Curves: walk from every vertex of degree other than 2 along degree-2 vertices; what is left
// unvisited are loops made only of degree-2 vertices.
void Curve_network::trace_curves() {
  std::vector<bool> used(m_segments.size(), false);
  auto other = [&](std::size_t s, std::size_t v) {
    return m_segments[s][0] == v ? m_segments[s][1] : m_segments[s][0];
  };
  auto walk = [&](std::size_t start, std::size_t s) {
    Curve c;
    c.vertices.push_back(start);
    std::size_t v = start;
    while (true) {
      used[s] = true;
      v = other(s, v);
      c.vertices.push_back(v);
      if (degree(v) != 2 || v == start) break;
      const Index_range inc = incident_segments(v);
      s = used[inc[0]] ? inc[1] : inc[0];
      if (used[s]) break;
    }
    c.closed = c.vertices.front() == c.vertices.back();
    m_curves.push_back(std::move(c));
  };
  for (std::size_t v = 0; v < m_points.size(); ++v)
    if (degree(v) != 2)
      for (std::size_t s : incident_segments(v))
        if (!used[s]) walk(v, s);
  for (std::size_t v = 0; v < m_points.size(); ++v)
    for (std::size_t s : incident_segments(v))
      if (!used[s]) walk(v, s);
}

std::vector<std::size_t> Curve_network::feature_points() const {
  std::vector<std::size_t> out;
  for (std::size_t v = 0; v < m_points.size(); ++v)
    if (is_feature_point(v)) out.push_back(v);
  return out;
}

std::vector<std::size_t> Curve_network::endpoints() const {
  std::vector<std::size_t> out;
  for (std::size_t v = 0; v < m_points.size(); ++v)
    if (is_endpoint(v)) out.push_back(v);
  return out;
}

std::size_t Curve_network::number_of_closed_polylines() const {
  return static_cast<std::size_t>(std::count_if(
      m_polylines.begin(), m_polylines.end(),
      [](const std::vector<std::size_t>& p) { return p.size() > 2 && p.front() == p.back(); }));
}

std::vector<std::size_t> Curve_network::non_planar_segments() const {
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                                      boost::property<boost::edge_index_t, std::size_t>>;
  Graph g(m_points.size());
  for (std::size_t k = 0; k < m_segments.size(); ++k) boost::add_edge(m_segments[k][0], m_segments[k][1], k, g);
  std::vector<boost::graph_traits<Graph>::edge_descriptor> kuratowski;
  if (boost::boyer_myrvold_planarity_test(boost::boyer_myrvold_params::graph = g,
                                          boost::boyer_myrvold_params::kuratowski_subgraph =
                                              std::back_inserter(kuratowski)))
    return {};
  std::vector<std::size_t> out;
  for (const auto& e : kuratowski) out.push_back(boost::get(boost::edge_index, g, e));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::size_t> Curve_network::polylines_of_segments(const std::vector<std::size_t>& segments) const {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < m_polylines.size(); ++k) {
    const auto& pl = m_polylines[k];
    bool hit = false;
    for (std::size_t i = 0; i + 1 < pl.size() && !hit; ++i)
      for (std::size_t s : segments) {
        const Segment& sg = m_segments[s];
        if ((sg[0] == pl[i] && sg[1] == pl[i + 1]) || (sg[1] == pl[i] && sg[0] == pl[i + 1])) {
          hit = true;
          break;
        }
      }
    if (hit) out.push_back(k);
  }
  return out;
}

std::size_t Curve_network::number_of_independent_cycles() const {
  return m_segments.size() + m_number_of_components - m_points.size();
}

namespace {

// The polylines of a file in CGAL's polyline format, and each one's line.
void parse_polylines(const std::string& content, const std::string& name,
                     std::vector<Curve_network::Polyline>& polylines, std::vector<Input_location>& where) {
  // One token per line in tokens(): a polyline of millions of points is read from its line
  // directly, without an array of its tokens (which would take several times the file's size).
  internal::Line_reader in(content, name, '#', 1);
  while (in.next()) {
    const std::string_view line = in.line();
    const std::string_view first = in.tokens()[0];
    const std::uint64_t n = in.to_unsigned(first, "point count");
    if (n < 2) in.fail("a polyline needs at least 2 points, this one declares " + std::to_string(n));
    std::size_t pos = static_cast<std::size_t>(first.data() + first.size() - line.data());
    const std::size_t coordinates = internal::count_tokens(line.substr(pos));
    // (3 n is not computed: it wraps for a declared count near 2^64.)
    if (coordinates % 3 != 0 || coordinates / 3 != n)
      in.fail("the polyline declares " + std::to_string(n) + " points (3 coordinates each) but the line has " +
              std::to_string(coordinates) + " coordinates");
    Curve_network::Polyline pl;
    pl.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = in.to_double(internal::next_token(line, pos), "x coordinate");
      const double y = in.to_double(internal::next_token(line, pos), "y coordinate");
      const double z = in.to_double(internal::next_token(line, pos), "z coordinate");
      pl.emplace_back(x, y, z);
    }
    polylines.push_back(std::move(pl));
    where.push_back(in.here());
  }
  if (polylines.empty())
    throw Invalid_input(Input_location{name, 0, Input_location::no_offset},
                        "the file has no polyline");
}

// The network of parse_polylines' result; an error without a place is placed in the file.
Curve_network network_of_polylines(const std::vector<Curve_network::Polyline>& polylines,
                                   const std::vector<Input_location>& where, const std::string& name,
                                   double relative_tolerance) {
  try {
    return Curve_network(polylines, relative_tolerance, where);
  } catch (const Invalid_input& e) {
    if (!e.where().file.empty()) throw;
    throw Invalid_input(Input_location{name, 0, Input_location::no_offset}, e.problem());
  }
}

}  // namespace

Curve_network parse_curve_network(const std::string& content, const std::string& name,
                                  double relative_tolerance) {
  std::vector<Curve_network::Polyline> polylines;
  std::vector<Input_location> where;
  parse_polylines(content, name, polylines, where);
  return network_of_polylines(polylines, where, name, relative_tolerance);
}

namespace {

// The curve edges of a mesh file (OBJ `l` lines, PLY edges flagged `curve`) as two-point polylines:
// the network's merging joins them into chains again.
Curve_network curve_network_of_mesh_file(const std::string& content, const std::string& name, bool ply,
                                         double relative_tolerance) {
  const internal::Polygon_soup soup = ply ? internal::parse_ply(content, name) : internal::parse_obj(content, name);
  if (soup.edges.empty())
    throw Invalid_input(Input_location{name, 0, Input_location::no_offset},
                        ply ? "the PLY file has no curve edges (an 'edge' element with vertex1, vertex2 and a "
                              "nonzero integer property 'curve'" +
                                  std::string(soup.ignored_edges ? "; its " + std::to_string(soup.ignored_edges) +
                                                                       " edges carry no curve flag)"
                                                                 : ")")
                            : "the OBJ file has no curve edges ('l' lines)");
  std::vector<Curve_network::Polyline> polylines;
  std::vector<Input_location> where;
  polylines.reserve(soup.edges.size());
  for (std::size_t e = 0; e < soup.edges.size(); ++e) {
    const Input_location at = soup.location(soup.edge_where[e]);
    for (std::size_t v : soup.edges[e])
      if (v >= soup.points.size())
        throw Invalid_input(at, "curve edge refers to vertex " + std::to_string(soup.one_based ? v + 1 : v) +
                                    ", but there are only " + std::to_string(soup.points.size()) + " vertices");
    polylines.push_back({soup.points[soup.edges[e][0]], soup.points[soup.edges[e][1]]});
    where.push_back(at);
  }
  return Curve_network(polylines, relative_tolerance, where);
}

std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

Curve_network read_curve_network(const std::string& path, double relative_tolerance) {
  const std::string ext = lower_extension(path);
  if (ext == "obj" || ext == "ply")
    return curve_network_of_mesh_file(internal::read_file(path), path, ext == "ply", relative_tolerance);
  // The file's text is let go before the network is built, rather than kept through the merge
  // (a 108 MB line of 1.7 M points peaked at 437 MB with both).
  std::vector<Curve_network::Polyline> polylines;
  std::vector<Input_location> where;
  parse_polylines(internal::read_file(path), path, polylines, where);
  return network_of_polylines(polylines, where, path, relative_tolerance);
}

void write_curve_network(const std::string& path, const Curve_network& network) {
  internal::write_file_atomically(path, [&](std::ostream& os) {
    os.precision(17);
    for (const auto& c : network.curves()) {
      os << c.vertices.size();
      for (std::size_t v : c.vertices) {
        const Point_3& p = network.point(v);
        os << ' ' << p.x() << ' ' << p.y() << ' ' << p.z();
      }
      os << '\n';
    }
  });
}

}  // namespace meshfit

namespace meshfit {
namespace internal {

Resampled_network resample_long_segments(const Curve_network& network, double spacing, const std::vector<bool>& whole) {
  Resampled_network r;
  const std::size_t nv = network.number_of_vertices();
  const auto& segments = network.segments();
  // The points added on each segment, from its lower-numbered end, computed once: a segment
  // written twice (in either direction) gets the same points.
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> index;
  std::vector<std::vector<Point_3>> inner(segments.size());
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::size_t a = std::min(segments[k][0], segments[k][1]), b = std::max(segments[k][0], segments[k][1]);
    index[{a, b}] = k;
    const Point_3 &pa = network.point(a), &pb = network.point(b);
    const double length = std::sqrt(CGAL::squared_distance(pa, pb));
    if (!(spacing > 0) || !(length > 2 * spacing) || (k < whole.size() && whole[k])) continue;
    const double pieces = std::ceil(length / spacing);
    for (double j = 1; j < pieces; ++j) inner[k].push_back(pa + (j / pieces) * (pb - pa));
    r.added += inner[k].size();
  }
  if (r.added == 0) {
    r.network = network;
    r.vertex_of.resize(nv);
    std::iota(r.vertex_of.begin(), r.vertex_of.end(), std::size_t(0));
    r.segment_of = r.vertex_of;
    r.segment_of.resize(segments.size());
    std::iota(r.segment_of.begin(), r.segment_of.end(), std::size_t(0));
    return r;
  }
  std::vector<Curve_network::Polyline> lines;
  for (const auto& pl : network.polylines()) {
    Curve_network::Polyline line{network.point(pl[0])};
    for (std::size_t i = 0; i + 1 < pl.size(); ++i) {
      const auto& pts = inner[index.at({std::min(pl[i], pl[i + 1]), std::max(pl[i], pl[i + 1])})];
      if (pl[i] < pl[i + 1]) line.insert(line.end(), pts.begin(), pts.end());
      else line.insert(line.end(), pts.rbegin(), pts.rend());
      line.push_back(network.point(pl[i + 1]));
    }
    lines.push_back(std::move(line));
  }
  // Far from the origin (the example translated by 1e15) the added points round onto their
  // neighbours, and the network refuses the zero-length segments: that is not the user's input.
  Curve_network dense;
  try {
    dense = Curve_network(lines, network.relative_tolerance());
  } catch (const Invalid_input&) {
    return resample_long_segments(network, 0);
  }
  // Which original vertex or segment each vertex of the dense network comes from.
  std::vector<std::size_t> origin(dense.number_of_vertices(), SIZE_MAX), on_segment(dense.number_of_vertices(), SIZE_MAX);
  bool distinct = dense.number_of_vertices() == nv + r.added;
  r.vertex_of.assign(nv, SIZE_MAX);
  for (std::size_t v = 0; v < nv && distinct; ++v) {
    const auto w = dense.find_vertex(network.point(v));
    distinct = w && origin[*w] == SIZE_MAX;
    if (distinct) origin[r.vertex_of[v] = *w] = v;
  }
  for (std::size_t k = 0; k < segments.size() && distinct; ++k)
    for (const Point_3& p : inner[k]) {
      const auto w = dense.find_vertex(p);
      distinct = w && origin[*w] == SIZE_MAX && on_segment[*w] == SIZE_MAX;
      if (!distinct) break;
      on_segment[*w] = k;
    }
  if (!distinct) return resample_long_segments(network, 0);  // curves too close to cut: as they are
  r.network = std::move(dense);
  for (const auto& s : r.network.segments()) {
    std::size_t k = on_segment[s[0]] != SIZE_MAX ? on_segment[s[0]] : on_segment[s[1]];
    if (k == SIZE_MAX) k = index.at({std::min(origin[s[0]], origin[s[1]]), std::max(origin[s[0]], origin[s[1]])});
    r.segment_of.push_back(k);
  }
  return r;
}

}  // namespace internal
}  // namespace meshfit

#pragma GCC diagnostic pop
