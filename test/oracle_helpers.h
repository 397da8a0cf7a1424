// The tests' side of the independent oracle, bench/battery/fit_oracle.h (issue 15): a fit or a
// partition is judged by what CGAL finds on the result, not by meshfit's own verification.
#ifndef MESHFIT_TEST_ORACLE_HELPERS_H
#define MESHFIT_TEST_ORACLE_HELPERS_H

#include "fit_oracle.h"

#include <meshfit/curve_network.h>

#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <catch2/catch.hpp>

#include <string>

namespace meshfit_test {

/// The network's polylines as points, for fit_oracle::network_of.
inline fit_oracle::Polylines polylines_of(const meshfit::Curve_network& network) {
  fit_oracle::Polylines out;
  for (const auto& ids : network.polylines()) {
    std::vector<fit_oracle::Point_3> pl;
    for (std::size_t v : ids) pl.push_back(network.point(v));
    out.push_back(pl);
  }
  return out;
}

inline fit_oracle::Network oracle_network(const meshfit::Curve_network& network) {
  return fit_oracle::network_of(polylines_of(network));
}

/// The oracle's findings in one line, for INFO.
inline std::string describe(const fit_oracle::Fit_check& c) {
  std::string s = "oracle: " + std::to_string(c.embedding.regions) + " regions, " +
                  std::to_string(c.segments - c.embedding.not_chained) + " of " + std::to_string(c.segments) +
                  " segments chains, smallest angle " + std::to_string(c.smallest_angle_deg) + " deg";
  for (const std::string& p : c.problems()) s += "; " + p;
  return s;
}

/// Whether the oracle passes `c`; its findings go with the next assertion (CHECK(oracle_passes(c))).
inline bool oracle_passes(const fit_oracle::Fit_check& c) {
  UNSCOPED_INFO(describe(c));
  return c.passed();
}

#ifdef MESHFIT_EXAMPLE_DATA_DIR
/// The oracle on a fit of the embedded example (any FaceGraph): its template and curves read with
/// CGAL and the oracle's own reader, 12 regions expected.
template <typename FaceGraph>
fit_oracle::Fit_check check_example_fit(const FaceGraph& result) {
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  fit_oracle::Mesh tmpl;
  if (!CGAL::IO::read_polygon_mesh(d + "/template.off", tmpl)) throw std::runtime_error("cannot read the example template");
  return fit_oracle::check_fit(fit_oracle::copy_of(result), tmpl,
                               fit_oracle::network_of(fit_oracle::read_polylines(d + "/curves.polylines.txt")), 12);
}
#endif

}  // namespace meshfit_test

#endif  // MESHFIT_TEST_ORACLE_HELPERS_H
