#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/threads.h>

#include "fp_traps.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <string>

namespace meshfit {

namespace {

// OpenBLAS (the BLAS CMake links, BLA_VENDOR OpenBLAS) runs on one thread under CHOLMOD's
// supernodal factorisation (internal::Scoped_openblas_threads, threads.h). CHOLMOD's supernodes
// are small on a surface mesh: threaded BLAS calls on them cost more than they save (the
// 164 000-vertex system of a 327 680-face template: 37 s on OpenBLAS's threads beside other work,
// 5 s on one), and one thread makes the result independent of the machine's cores.
constexpr int cholmod_blas_threads = 1;

using Sparse = Eigen::SparseMatrix<double>;

// A x = rhs for a symmetric positive definite A, by CHOLMOD's supernodal factorisation (its own
// fill-reducing ordering). `what` names the system in the Numerical_error thrown when the
// factorisation or the solve fails, or the solution is not finite.
Eigen::MatrixXd solve_definite(const Sparse& A, const Eigen::MatrixXd& rhs, const char* what) {
  const internal::Scoped_openblas_threads one_thread(cholmod_blas_threads);
  Eigen::CholmodSupernodalLLT<Sparse, Eigen::Lower> solver;
  solver.compute(A);
  const std::string size = std::to_string(A.rows()) + "×" + std::to_string(A.cols());
  if (solver.info() != Eigen::Success)
    throw Numerical_error("displacement: the sparse Cholesky factorisation of the " + size + " " + what + " failed");
  Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite())
    throw Numerical_error("displacement: the sparse solve of the " + size + " " + what +
                          " failed or gave a non-finite value");
  return x;
}

// One constraint flag and one displacement per vertex.
void check_sizes(std::size_t n, const std::vector<bool>& constrained, const std::vector<Vector_3>& given) {
  if (constrained.size() != n || given.size() != n)
    throw Invalid_input("displacement: " + std::to_string(n) + " vertices but " + std::to_string(constrained.size()) +
                        " constraint flags and " + std::to_string(given.size()) + " displacements");
}

// K = D − A, the symmetric graph Laplacian of the adjacency, and D⁻¹ (0 for an isolated vertex).
Sparse graph_laplacian(const Vertex_adjacency& adj, Eigen::VectorXd& inverse_degree) {
  const std::size_t n = adj.size();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(n + adj.neighbours.size());
  inverse_degree.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t deg = adj.offsets[i + 1] - adj.offsets[i];
    const auto ii = static_cast<Eigen::Index>(i);
    inverse_degree(ii) = deg > 0 ? 1.0 / static_cast<double>(deg) : 0.0;
    t.emplace_back(ii, ii, static_cast<double>(deg));
    for (std::size_t k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k)
      t.emplace_back(ii, static_cast<Eigen::Index>(adj.neighbours[k]), -1.0);
  }
  const auto N = static_cast<Eigen::Index>(n);
  Sparse K(N, N);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

// Whether each vertex's connected part holds a marked vertex.
std::vector<bool> reaches(const Vertex_adjacency& adj, const std::vector<bool>& marked) {
  const std::size_t n = adj.size();
  std::vector<bool> out(n, false);
  std::vector<std::size_t> part(n, SIZE_MAX), stack, members;
  for (std::size_t s = 0; s < n; ++s) {
    if (part[s] != SIZE_MAX) continue;
    bool any = false;
    members.clear();
    stack.assign(1, s);
    part[s] = s;
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      members.push_back(v);
      any = any || marked[v];
      for (std::size_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
        const std::size_t w = adj.neighbours[k];
        if (part[w] == SIZE_MAX) part[w] = s, stack.push_back(w);
      }
    }
    if (any)
      for (std::size_t v : members) out[v] = true;
  }
  return out;
}

}  // namespace

std::vector<Vector_3> interpolate_displacements(const Vertex_adjacency& adj, const std::vector<bool>& constrained,
                                                const std::vector<Vector_3>& given, int order,
                                                Displacement_report* report) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  check_sizes(n, constrained, given);
  if (order != 1 && order != 2) throw Invalid_input("displacement: order must be 1 or 2, not " + std::to_string(order));
  for (std::size_t i = 0; i < n; ++i)
    if (constrained[i] && !(std::isfinite(given[i].x()) && std::isfinite(given[i].y()) && std::isfinite(given[i].z())))
      throw Invalid_input("displacement: the displacement of vertex " + std::to_string(i) + " is not finite");

  // Connected parts with no constrained vertex keep a zero displacement: they are held, which
  // also keeps the system definite.
  std::vector<bool> held = constrained;
  std::vector<Vector_3> d(n, Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < n; ++i)
    if (constrained[i]) d[i] = given[i];
  Displacement_report r;
  const std::vector<bool> reached = reaches(adj, constrained);
  for (std::size_t i = 0; i < n; ++i)
    if (!reached[i]) held[i] = true, ++r.unconstrained_free_vertices;
  std::vector<std::ptrdiff_t> free_index(n, -1);
  std::ptrdiff_t nf = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!held[i]) free_index[i] = nf++;
  r.free_vertices = static_cast<std::size_t>(nf);
  r.constrained_vertices = n - r.free_vertices - r.unconstrained_free_vertices;
  if (nf == 0) {
    if (report) *report = r;
    return d;
  }

  // K = D − A, the symmetric graph Laplacian; the membrane energy is dᵀK d, the thin-plate one
  // dᵀ K D⁻¹ K d (the squared uniform Laplacian D⁻¹K d weighted by the degree).
  Eigen::VectorXd inverse_degree;
  const Sparse K = graph_laplacian(adj, inverse_degree);
  Sparse Q = order == 1 ? K : Sparse(K * inverse_degree.asDiagonal() * K);

  // Q_FF x_F = −Q_FC d_C. The free indices grow with the vertex indices, so Q_FF's columns and
  // rows come out of Q's in order: it is written column by column, with no triplets to sort (12 M
  // of them at 1.3e6 faces).
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nf, 3);
  Sparse A(nf, nf);
  A.reserve(Q.nonZeros());
  for (Eigen::Index c = 0; c < Q.outerSize(); ++c) {
    const std::ptrdiff_t col = free_index[static_cast<std::size_t>(c)];
    if (col >= 0) A.startVec(col);
    for (Sparse::InnerIterator it(Q, c); it; ++it) {
      const std::ptrdiff_t row = free_index[static_cast<std::size_t>(it.row())];
      if (row < 0) continue;
      if (col >= 0) {
        A.insertBack(row, col) = it.value();
      } else {
        const Vector_3& g = d[static_cast<std::size_t>(c)];
        rhs(row, 0) -= it.value() * g.x();
        rhs(row, 1) -= it.value() * g.y();
        rhs(row, 2) -= it.value() * g.z();
      }
    }
  }
  A.finalize();
  // Symmetric positive definite: every part of the mesh has a held vertex.
  const Eigen::MatrixXd x = solve_definite(A, rhs, "system");
  r.nonzeros = static_cast<std::size_t>(A.nonZeros());
  for (std::size_t i = 0; i < n; ++i)
    if (free_index[i] >= 0) d[i] = Vector_3(x(free_index[i], 0), x(free_index[i], 1), x(free_index[i], 2));
  if (report) *report = r;
  return d;
}

std::vector<bool> vertices_within_reach(const Vertex_adjacency& adj, const std::vector<bool>& constrained,
                                        const std::vector<Vector_3>& given, double edge, std::size_t rings,
                                        double fade) {
  const std::size_t n = adj.size();
  check_sizes(n, constrained, given);
  if (!(edge > 0)) throw Invalid_input("displacement: the edge length must be positive, not " + internal::format_number(edge));
  // A breadth-first search carrying the most rings left, in buckets by rings left.
  std::vector<std::ptrdiff_t> rings_left(n, -1);
  std::vector<std::vector<std::size_t>> by_rings_left;
  for (std::size_t i = 0; i < n; ++i) {
    if (!constrained[i]) continue;
    const double r = std::ceil(fade * std::sqrt(given[i].squared_length()) / edge);
    const std::size_t ri = r < static_cast<double>(n) ? std::max(rings, static_cast<std::size_t>(r)) : n;
    rings_left[i] = static_cast<std::ptrdiff_t>(ri);
    if (by_rings_left.size() <= ri) by_rings_left.resize(ri + 1);
    by_rings_left[ri].push_back(i);
  }
  for (std::size_t r = by_rings_left.size(); r-- > 1;)
    for (std::size_t i : by_rings_left[r]) {
      if (rings_left[i] != static_cast<std::ptrdiff_t>(r)) continue;  // reached with more since
      for (std::size_t k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
        const std::size_t j = adj.neighbours[k];
        if (rings_left[j] + 1 < static_cast<std::ptrdiff_t>(r)) {
          rings_left[j] = static_cast<std::ptrdiff_t>(r) - 1;
          by_rings_left[r - 1].push_back(j);
        }
      }
    }
  std::vector<bool> in(n);
  for (std::size_t i = 0; i < n; ++i) in[i] = rings_left[i] >= 0;
  return in;
}

std::vector<Vector_3> fit_displacements(const Vertex_adjacency& adj, const std::vector<Soft_displacement>& constraints,
                                        double stiffness) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  if (!std::isfinite(stiffness) || !(stiffness > 0))
    throw Invalid_input("displacement: the stiffness must be positive, not " + internal::format_number(stiffness));
  Eigen::VectorXd inverse_degree;
  const Sparse K = graph_laplacian(adj, inverse_degree);
  const auto N = static_cast<Eigen::Index>(n);
  Sparse A = stiffness * Sparse(K * inverse_degree.asDiagonal() * K);
  std::vector<Eigen::Triplet<double>> t;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(N, 3);
  for (const Soft_displacement& c : constraints) {
    for (std::size_t a = 0; a < 3; ++a)
      if (c.corners[a] >= n) throw Invalid_input("displacement: a constraint's corner " + std::to_string(c.corners[a]) + " is out of range");
    if (!(std::isfinite(c.target.x()) && std::isfinite(c.target.y()) && std::isfinite(c.target.z())))
      throw Invalid_input("displacement: a constraint's target is not finite");
    if (!(std::isfinite(c.weight) && c.weight >= 0) ||
        !std::all_of(c.barycentric.begin(), c.barycentric.end(), [](double b) { return std::isfinite(b); }))
      throw Invalid_input("displacement: a constraint's weight must be finite and not negative, its coordinates finite");
    for (std::size_t a = 0; a < 3; ++a) {
      const auto ia = static_cast<Eigen::Index>(c.corners[a]);
      const double wa = c.weight * c.barycentric[a];
      rhs(ia, 0) += wa * c.target.x();
      rhs(ia, 1) += wa * c.target.y();
      rhs(ia, 2) += wa * c.target.z();
      for (std::size_t b = 0; b < 3; ++b)
        t.emplace_back(ia, static_cast<Eigen::Index>(c.corners[b]), wa * c.barycentric[b]);
    }
  }
  // Parts of the mesh without a constraint keep a zero displacement (an identity row); elsewhere
  // the data term is definite on the constants, the thin-plate energy's kernel in each part.
  std::vector<bool> touched(n, false);
  for (const Soft_displacement& c : constraints)
    for (std::size_t a = 0; a < 3; ++a)
      if (c.barycentric[a] != 0 && c.weight != 0) touched[c.corners[a]] = true;
  const std::vector<bool> reached = reaches(adj, touched);
  for (std::size_t i = 0; i < n; ++i)
    if (!reached[i]) t.emplace_back(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i), 1.0);
  Sparse data(N, N);
  data.setFromTriplets(t.begin(), t.end());
  A += data;
  const Eigen::MatrixXd x = solve_definite(A, rhs, "fitting system");
  std::vector<Vector_3> d(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    d[i] = Vector_3(x(ii, 0), x(ii, 1), x(ii, 2));
  }
  return d;
}

}  // namespace meshfit
