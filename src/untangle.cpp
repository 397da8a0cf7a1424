#include <meshfit/exceptions.h>
#include <meshfit/untangle.h>

#include <Eigen/Dense>
#include <LBFGS.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace meshfit {
namespace {

// χ(D, ε) of the paper, in the form that does not cancel for D < 0, and its derivative in D.
double chi(double eps, double det) {
  const double r = std::sqrt(eps * eps + det * det);
  return det > 0 ? (det + r) / 2 : eps * eps / (2 * (r - det));
}
double chi_derivative(double eps, double det) { return 0.5 + det / (2 * std::sqrt(eps * eps + det * det)); }

// Two unit vectors completing n / |n| to an orthonormal frame.
std::array<Eigen::Vector3d, 2> tangent_frame(const Vector_3& n) {
  const Eigen::Vector3d u = Eigen::Vector3d(n.x(), n.y(), n.z()).normalized();
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  int k = 0;
  u.cwiseAbs().minCoeff(&k);
  axis[k] = 1;
  const Eigen::Vector3d t1 = u.cross(axis).normalized();
  return {t1, u.cross(t1)};
}

struct Budget_spent {};

struct Patch {
  // Per face in the energy: corners, projection frame, the inverse of its reference shape.
  std::vector<std::array<std::size_t, 3>> corners;
  std::vector<std::array<Eigen::Vector3d, 2>> frame;
  Eigen::Matrix2d reference_inverse;
  double theta = 1.0 / 128;
  // Per vertex of the patch: its start; for a free one its first variable (of two, its motion in
  // its plane) or -1 when held, and that plane; its neighbours (complete for the free ones).
  std::vector<Eigen::Vector3d> start;
  std::vector<std::ptrdiff_t> variable;
  std::vector<std::array<Eigen::Vector3d, 2>> plane;
  std::vector<std::vector<std::size_t>> neighbours;
  double fairness = 0;
  // Where the patch sits: patch vertex -> vertex, and the frame of its coordinates.
  std::vector<std::size_t> global;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double unit = 1;
  std::ptrdiff_t variables = 0;

  Eigen::Vector3d position(std::size_t v, const Eigen::VectorXd& x) const {
    if (variable[v] < 0) return start[v];
    return start[v] + x[variable[v]] * plane[v][0] + x[variable[v] + 1] * plane[v][1];
  }
  void add_gradient(std::size_t v, const Eigen::Vector3d& g, Eigen::VectorXd& grad) const {
    if (variable[v] < 0) return;
    grad[variable[v]] += g.dot(plane[v][0]);
    grad[variable[v] + 1] += g.dot(plane[v][1]);
  }
  Eigen::Matrix2d jacobian(std::size_t f, const Eigen::VectorXd& x) const {
    const auto& c = corners[f];
    const Eigen::Vector3d a = position(c[0], x), e1 = position(c[1], x) - a, e2 = position(c[2], x) - a;
    Eigen::Matrix2d D;
    D << e1.dot(frame[f][0]), e2.dot(frame[f][0]), e1.dot(frame[f][1]), e2.dot(frame[f][1]);
    return D * reference_inverse;
  }
  double min_det(const Eigen::VectorXd& x, std::size_t* inverted = nullptr) const {
    double m = std::numeric_limits<double>::infinity();
    if (inverted) *inverted = 0;
    for (std::size_t f = 0; f < corners.size(); ++f) {
      const double d = jacobian(f, x).determinant();
      m = std::min(m, d);
      if (inverted && d <= 0) ++*inverted;
    }
    return m;
  }
  // The energy at x with parameter eps, and its gradient.
  double energy(const Eigen::VectorXd& x, Eigen::VectorXd& grad, double eps) const {
    grad.setZero(x.size());
    double E = 0;
    for (std::size_t f = 0; f < corners.size(); ++f) {
      const Eigen::Matrix2d J = jacobian(f, x);
      const double det = J.determinant();
      const double c = std::max(chi(eps, det), 1e-200), dc = chi_derivative(eps, det);
      Eigen::Matrix2d K;  // d det / d J
      K << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
      const double shape = J.squaredNorm() / c, area = (1 + det * det) / c;
      E += (1 - theta) * shape + theta * area;
      const Eigen::Matrix2d dJ = (1 - theta) * (2 * J / c - shape * dc / c * K) +
                                 theta * (2 * det / c * K - area * dc / c * K);
      const Eigen::Matrix2d dD = dJ * reference_inverse.transpose();  // columns: d/d e1, d/d e2
      const auto& cf = corners[f];
      const Eigen::Vector3d g1 = dD(0, 0) * frame[f][0] + dD(1, 0) * frame[f][1];
      const Eigen::Vector3d g2 = dD(0, 1) * frame[f][0] + dD(1, 1) * frame[f][1];
      const Eigen::Vector3d g[3] = {-g1 - g2, g1, g2};
      for (int k = 0; k < 3; ++k) add_gradient(cf[k], g[k], grad);
    }
    // Fairness: each free vertex drawn towards its neighbours' mean.
    for (std::size_t v = 0; v < start.size(); ++v) {
      if (variable[v] < 0) continue;
      const double w = 1.0 / static_cast<double>(neighbours[v].size());
      Eigen::Vector3d l = position(v, x);
      for (std::size_t u : neighbours[v]) l -= w * position(u, x);
      E += fairness * l.squaredNorm();
      add_gradient(v, 2 * fairness * l, grad);
      for (std::size_t u : neighbours[v]) add_gradient(u, -2 * fairness * w * l, grad);
    }
    return E;
  }
};

// The faces with a free corner, and the vertices they touch, renumbered; coordinates relative to
// the patch's centroid in units of its mean edge length, so the energy's scale is the same
// wherever the patch lies and whatever its size. None when no face has a free corner or the
// patch has no extent.
std::optional<Patch> make_patch(const std::vector<Point_3>& positions, const std::vector<std::array<std::size_t, 3>>& faces,
                                const std::vector<Vector_3>& face_normal, const std::vector<bool>& free,
                                const std::vector<Vector_3>& vertex_normal, double fairness, Untangle_report& r) {
  const std::size_t n = positions.size();
  Patch patch;
  std::vector<std::size_t> local(n, SIZE_MAX);
  std::vector<std::size_t>& global = patch.global;
  std::vector<std::size_t> kept;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& c = faces[f];
    for (std::size_t v : c)
      if (v >= n) throw Invalid_input("untangle: face " + std::to_string(f) + " has a corner out of range");
    if (!(free[c[0]] || free[c[1]] || free[c[2]])) continue;
    if (face_normal[f] == CGAL::NULL_VECTOR) throw Invalid_input("untangle: face " + std::to_string(f) + " has a zero normal");
    kept.push_back(f);
    for (std::size_t v : c)
      if (local[v] == SIZE_MAX) local[v] = global.size(), global.push_back(v);
  }
  if (kept.empty()) return std::nullopt;
  Eigen::Vector3d& centre = patch.centre;
  for (std::size_t v : global) centre += Eigen::Vector3d(positions[v].x(), positions[v].y(), positions[v].z());
  centre /= static_cast<double>(global.size());
  double edge_sum = 0;
  for (std::size_t f : kept)
    for (int k = 0; k < 3; ++k) edge_sum += std::sqrt(CGAL::squared_distance(positions[faces[f][k]], positions[faces[f][(k + 1) % 3]]));
  const double unit = patch.unit = edge_sum / (3.0 * static_cast<double>(kept.size()));
  if (!(unit > 0) || !std::isfinite(unit)) return std::nullopt;

  std::ptrdiff_t& variables = patch.variables;
  for (std::size_t v : global) {
    patch.start.push_back((Eigen::Vector3d(positions[v].x(), positions[v].y(), positions[v].z()) - centre) / unit);
    patch.variable.push_back(free[v] ? variables : -1);
    patch.plane.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});  // a held vertex has no plane
    if (!free[v]) continue;
    if (vertex_normal[v] == CGAL::NULL_VECTOR) throw Invalid_input("untangle: vertex " + std::to_string(v) + " has a zero normal");
    patch.plane.back() = tangent_frame(vertex_normal[v]);
    variables += 2, ++r.free_vertices;
  }
  patch.neighbours.resize(global.size());
  for (std::size_t f : kept) {
    const std::array<std::size_t, 3> c{local[faces[f][0]], local[faces[f][1]], local[faces[f][2]]};
    patch.corners.push_back(c);
    patch.frame.push_back(tangent_frame(face_normal[f]));
    for (int k = 0; k < 3; ++k)
      for (int l = 1; l < 3; ++l) {
        auto& nb = patch.neighbours[c[k]];
        if (std::find(nb.begin(), nb.end(), c[(k + l) % 3]) == nb.end()) nb.push_back(c[(k + l) % 3]);
      }
  }
  patch.fairness = fairness;
  r.faces = kept.size();

  // The reference: an equilateral triangle of the faces' mean projected area.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(variables);
  double area = 0;
  {
    patch.reference_inverse.setIdentity();
    for (std::size_t f = 0; f < patch.corners.size(); ++f) area += std::abs(patch.jacobian(f, x).determinant()) / 2;
    area /= static_cast<double>(patch.corners.size());
  }
  if (!(area > 0)) return std::nullopt;
  const double side = std::sqrt(4 * area / std::sqrt(3.0));
  Eigen::Matrix2d reference;
  reference << side, side / 2, 0, side * std::sqrt(3.0) / 2;
  patch.reference_inverse = reference.inverse();
  return patch;
}

// Continuation in ε (the paper's schedule) from x: ε starts where the worst face's determinant
// is, and decreases as the energy does; it ends when no face is inverted and the energy settles.
void minimise(const Patch& patch, Eigen::VectorXd& x, Untangle_report& r) {
  double mindet = patch.min_det(x, &r.inverted_before);
  double eps = std::sqrt(1e-12 + 0.04 * std::pow(std::min(mindet, 0.0), 2));
  LBFGSpp::LBFGSParam<double> param;
  param.epsilon = 1e-8;
  param.epsilon_rel = 1e-8;
  param.max_iterations = 100;
  Eigen::VectorXd grad(patch.variables);
  // Bounded work: about 8e6 face evaluations in all (a second or two), whatever the patch.
  const std::size_t max_evaluations = std::max<std::size_t>(50, 8000000 / patch.corners.size());
  std::size_t evaluations = 0;
  // Where no placement of the free vertices untangles the patch (its held vertices are tangled
  // themselves), ε stops falling: give up after a few decreases that invert no fewer faces.
  std::size_t fewest_inverted = r.inverted_before, stalled = 0;
  for (std::size_t outer = 0; outer < 16 && stalled < 3; ++outer) {
    const double before = patch.energy(x, grad, eps);
    // The best point evaluated, kept whatever the line search does (it may give up, throwing, at
    // a point worse than the best).
    Eigen::VectorXd best = x;
    double best_energy = before;
    auto f = [&](const Eigen::VectorXd& y, Eigen::VectorXd& g) {
      if (++evaluations > max_evaluations) throw Budget_spent();
      const double e = patch.energy(y, g, eps);
      if (e < best_energy) best_energy = e, best = y;
      return e;
    };
    try {
      LBFGSpp::LBFGSSolver<double> solver(param);
      double fx = 0;
      solver.minimize(f, x, fx);
    } catch (const Budget_spent&) {
      x = best;
      ++r.outer_iterations;
      break;
    } catch (const std::exception&) {
      // the line search found no better step: the best point so far stands
    }
    x = best;
    ++r.outer_iterations;
    const double after = best_energy;
    std::size_t inverted = 0;
    mindet = patch.min_det(x, &inverted);
    // Untangled: a few more decreases of ε improve the shapes; stop when they no longer do.
    if (inverted == 0 && (outer >= 3 || before - after <= 1e-6 * std::abs(before))) break;
    if (inverted < fewest_inverted) fewest_inverted = inverted, stalled = 0;
    else ++stalled;
    const double sigma = std::max(1 - after / before, 0.1);
    const double mu = (1 - sigma) * chi(eps, mindet);
    eps = mindet < mu ? std::max(2 * std::sqrt(mu * (mu - mindet)), 1e-12) : 1e-12;
  }
  patch.min_det(x, &r.inverted_after);

}

}  // namespace

std::vector<Point_3> untangle_faces(const std::vector<Point_3>& positions,
                                    const std::vector<std::array<std::size_t, 3>>& faces,
                                    const std::vector<Vector_3>& face_normal, const std::vector<bool>& free,
                                    const std::vector<Vector_3>& vertex_normal, double fairness,
                                    Untangle_report* report) {
  const std::size_t n = positions.size();
  if (free.size() != n || vertex_normal.size() != n || face_normal.size() != faces.size())
    throw Invalid_input("untangle: " + std::to_string(n) + " positions, " + std::to_string(free.size()) +
                        " free flags, " + std::to_string(vertex_normal.size()) + " vertex normals, " +
                        std::to_string(faces.size()) + " faces and " + std::to_string(face_normal.size()) +
                        " face normals");
  if (!(fairness >= 0) || !std::isfinite(fairness))
    throw Invalid_input("untangle: the fairness weight must be finite and not negative");
  Untangle_report r;
  std::vector<Point_3> out = positions;
  if (const std::optional<Patch> patch = make_patch(positions, faces, face_normal, free, vertex_normal, fairness, r)) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(patch->variables);
    minimise(*patch, x, r);
    for (std::size_t i = 0; i < patch->global.size(); ++i) {
      if (patch->variable[i] < 0) continue;
      const Eigen::Vector3d p = patch->position(i, x) * patch->unit + patch->centre;
      out[patch->global[i]] = Point_3(p.x(), p.y(), p.z());
    }
  }
  if (report) *report = r;
  return out;
}

}  // namespace meshfit
