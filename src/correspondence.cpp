#include <meshfit/correspondence.h>

#include <meshfit/internal/format_number.h>

#include "point_set_predicates.h"
#include "io/text_parser.h"
#include "io/write_file.h"

#include <map>
#include <ostream>

namespace meshfit {

std::vector<Correspondence> parse_correspondences(const std::string& content, const std::string& name,
                                                  const Curve_network& network) {
  internal::Line_reader in(content, name);
  std::vector<Correspondence> pairs;
  std::map<std::size_t, std::size_t> by_template, by_network;  // vertex -> line
  while (in.next()) {
    const auto& t = in.tokens();
    const bool by_index = t.size() == 2 && !t[1].empty() && t[1][0] == '@';
    if (t.size() != 4 && !by_index)
      in.fail("expected 'template_vertex x y z' (4 values) or 'template_vertex @network_vertex' (2), found " +
              std::to_string(t.size()) + " values");
    Correspondence c;
    c.template_vertex = in.to_unsigned(t[0], "template vertex index");
    if (by_index) {
      const std::uint64_t k = in.to_unsigned(t[1].substr(1), "network vertex index (after '@')");
      if (k >= network.number_of_vertices())
        in.fail("network vertex @" + std::to_string(k) + " does not exist: the network has " +
                std::to_string(network.number_of_vertices()) +
                " vertices, @0 to @" + std::to_string(network.number_of_vertices() - 1) +
                " in order of first appearance in the curve file");
      c.network_vertex = static_cast<std::size_t>(k);
    } else {
      const Point_3 p(in.to_double(t[1], "x coordinate"), in.to_double(t[2], "y coordinate"),
                      in.to_double(t[3], "z coordinate"));
      const auto v = network.find_vertex(p);
      if (!v)
        in.fail("the point (" + std::string(t[1]) + ", " + std::string(t[2]) + ", " +
                std::string(t[3]) + ") is not a vertex of the curve network (tolerance " +
                internal::format_number(network.tolerance()) + ")");
      c.network_vertex = *v;
    }
    c.where = in.here();
    const auto t_it = by_template.emplace(c.template_vertex, in.line_number());
    if (!t_it.second)
      in.fail("template vertex " + std::to_string(c.template_vertex) + " is already paired on line " +
              std::to_string(t_it.first->second));
    const auto n_it = by_network.emplace(c.network_vertex, in.line_number());
    if (!n_it.second)
      in.fail("network vertex " + std::to_string(c.network_vertex) + " is already paired on line " +
              std::to_string(n_it.first->second));
    pairs.push_back(c);
  }
  return pairs;
}

std::vector<Correspondence> read_correspondences(const std::string& path, const Curve_network& network) {
  return parse_correspondences(internal::read_file(path), path, network);
}

void validate_correspondences(const std::vector<Correspondence>& pairs,
                              const std::vector<Point_3>& template_points,
                              const Curve_network& network, bool allow_coplanar_template) {
  const Input_location file_only =
      pairs.empty() ? Input_location{} : Input_location{pairs.front().where.file, 0, Input_location::no_offset};
  std::vector<Point_3> sources, targets;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Correspondence& c = pairs[i];
    const std::string name = c.where.line ? "" : "pair " + std::to_string(i) + ": ";
    if (c.template_vertex >= template_points.size())
      throw Invalid_input(c.where, name + "template vertex " + std::to_string(c.template_vertex) +
                                       " is out of range: the template has " +
                                       std::to_string(template_points.size()) + " vertices");
    if (c.network_vertex >= network.number_of_vertices())
      throw Invalid_input(c.where, name + "network vertex " + std::to_string(c.network_vertex) +
                                       " is out of range: the network has " +
                                       std::to_string(network.number_of_vertices()) + " vertices");
    sources.push_back(template_points[c.template_vertex]);
    targets.push_back(network.point(c.network_vertex));
  }
  if (pairs.size() < 4)
    throw Invalid_input(file_only, "at least 4 correspondences are needed, found " +
                                       std::to_string(pairs.size()));
  if (allow_coplanar_template) {
    if (internal::all_collinear(sources))
      throw Invalid_input(file_only, "the template vertices of the " + std::to_string(pairs.size()) +
                                         " correspondences are all collinear; the coarse RBF needs "
                                         "pairs spanning a plane at least");
  } else if (internal::all_coplanar(sources)) {
    throw Invalid_input(file_only, "the template vertices of the " + std::to_string(pairs.size()) +
                                       " correspondences are all coplanar; the coarse RBF needs "
                                       "pairs spanning 3D");
  }
  // Coplanar on both sides is the thesis's case for auxiliary pairs (Rbf_interpolant::fit); a plane
  // of network points for template vertices spanning 3D would flatten the template. Both judged
  // as the RBF and rounding see them, not exactly: a plane of points turned by a rotation is no
  // longer exactly one once rounded, and the verdict must not depend on where the input lies.
  if (internal::coplanar_within_rounding(targets) && !internal::nearly_coplanar(sources))
    throw Invalid_input(file_only, "the network points of the " + std::to_string(pairs.size()) +
                                       " correspondences are all coplanar but their template vertices are not: "
                                       "the coarse RBF would flatten the template; add a pair off that plane");
}

void write_correspondences(const std::string& path, const std::vector<Correspondence>& pairs,
                           const Curve_network& network) {
  internal::write_file_atomically(path, [&](std::ostream& os) {
    os.precision(17);
    os << "# template_vertex x y z\n";
    for (const Correspondence& c : pairs) {
      const Point_3& p = network.point(c.network_vertex);
      os << c.template_vertex << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
  });
}

}  // namespace meshfit
