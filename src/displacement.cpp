#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/threads.h>

#include "fp_traps.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

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
  solver.cholmod().print = 0;  // the library prints nothing: a failure is the exception below
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

// The rows of K (and M) that the energies share: vertex k's row over its border neighbours when
// it has any (weight 1, M_k their count: the Laplacian along the border), else over all of them
// with adj.weight (1 when empty) and M_k = adj.mass[k] (the number of neighbours when empty).
struct Laplacian_rows {
  const Vertex_adjacency& adj;
  bool has_border = false;
  std::vector<double> mass, diagonal;
  std::vector<bool> border_vertex;

  explicit Laplacian_rows(const Vertex_adjacency& a) : adj(a) {
    const std::size_t n = adj.size();
    if (!adj.border_edge.empty() && adj.border_edge.size() != adj.neighbours.size())
      throw Invalid_input("displacement: " + std::to_string(adj.border_edge.size()) + " border flags for " +
                          std::to_string(adj.neighbours.size()) + " neighbours");
    if ((!adj.weight.empty() && adj.weight.size() != adj.neighbours.size()) || (!adj.mass.empty() && adj.mass.size() != n))
      throw Invalid_input("displacement: " + std::to_string(adj.weight.size()) + " edge weights and " +
                          std::to_string(adj.mass.size()) + " masses for " + std::to_string(adj.neighbours.size()) +
                          " neighbours and " + std::to_string(n) + " vertices");
    has_border = std::find(adj.border_edge.begin(), adj.border_edge.end(), true) != adj.border_edge.end();
    mass.resize(n), diagonal.resize(n), border_vertex.assign(n, false);
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t b = 0;
      for (std::size_t m = adj.offsets[k]; m < adj.offsets[k + 1]; ++m) b += on_border(m);
      border_vertex[k] = b > 0;
      mass[k] = b > 0 ? static_cast<double>(b) : degree(k);
      diagonal[k] = mass[k];
      if (b == 0 && !adj.weight.empty()) {
        diagonal[k] = 0;
        for (std::size_t m = adj.offsets[k]; m < adj.offsets[k + 1]; ++m) diagonal[k] += adj.weight[m];
      }
      if (b == 0 && !adj.mass.empty()) mass[k] = adj.mass[k];
    }
  }
  double degree(std::size_t i) const { return static_cast<double>(adj.offsets[i + 1] - adj.offsets[i]); }
  bool on_border(std::size_t m) const { return has_border && adj.border_edge[m]; }
  // Whether neighbour position m of vertex k is in k's row, and its weight there.
  bool in_row(std::size_t k, std::size_t m) const { return !border_vertex[k] || on_border(m); }
  double weight(std::size_t k, std::size_t m) const { return adj.weight.empty() || border_vertex[k] ? 1.0 : adj.weight[m]; }
};


// The membrane (order 1: K = D − A, the symmetric graph Laplacian) or thin-plate (order 2:
// Kᵀ M⁻¹ K, the squared uniform Laplacian weighted by the number of neighbours it averages)
// energy's matrix, times `scale`, plus `extra` when given (a matrix of the same size). In the
// thin-plate energy a border vertex's row of K is taken along the border (over its border
// neighbours, M its count of them): the whole one-sided Laplacian there measures the slope
// across the border, and asking it to vanish held a fit's border flat (open-plane-saddle-boundary
// ended 1.04 % from the truth, 0.49 % so). Written column by column, each gathered in a scratch
// column of the mesh's size (an Eigen product K D⁻¹ K took 2.4 s at 655 362 vertices, this
// 0.2 s), with the operations of Eigen's product in its order (the sum over k ascending of
// (K_ki / M_k) K_kj, then the scale, then `extra`): the same numbers to the last bit, so that a
// fit does not change with the way its matrix is written.
Sparse energy_matrix(const Vertex_adjacency& adj, int order, double scale, const Sparse* extra = nullptr) {
  const std::size_t n = adj.size();
  const auto N = static_cast<Eigen::Index>(n);
  const Laplacian_rows rows(adj);
  auto degree = [&](std::size_t i) { return rows.degree(i); };
  auto on_border = [&](std::size_t m) { return rows.on_border(m); };
  auto weight = [&](std::size_t k, std::size_t m) { return rows.weight(k, m); };
  const std::vector<double>& row_count = rows.mass;
  const std::vector<double>& diagonal = rows.diagonal;
  const std::vector<bool>& border_vertex = rows.border_vertex;
  std::vector<double> value(n, 0.0);
  std::vector<bool> seen(n, false);
  std::vector<std::size_t> touched, column;
  std::vector<std::pair<std::size_t, double>> column_weight;
  // The membrane energy's diagonal: the sum of all of i's weights (no border rule there).
  auto diagonal_all = [&](std::size_t i) {
    double sum = 0;
    for (std::size_t m = adj.offsets[i]; m < adj.offsets[i + 1]; ++m) sum += adj.weight[m];
    return sum;
  };
  auto add = [&](std::size_t j, double v) {
    if (!seen[j]) seen[j] = true, touched.push_back(j), value[j] = v;
    else value[j] += v;
  };
  Sparse Q(N, N);
  Q.reserve(static_cast<Eigen::Index>((order == 1 ? 1 : 3) * adj.neighbours.size() + n +
                                      (extra ? static_cast<std::size_t>(extra->nonZeros()) : 0)));
  for (std::size_t i = 0; i < n; ++i) {
    touched.clear();
    // The rows k of K whose column i is not zero, ascending: i's own (when it has neighbours) and
    // its neighbours' (for order 2, but a border vertex's across an inner edge).
    column.clear();
    if (degree(i) > 0) column.push_back(i);
    // With the weight of edge ki, read from i's side (the same from k's), but 1 in a border row.
    column_weight.clear();
    for (std::size_t m = adj.offsets[i]; m < adj.offsets[i + 1]; ++m)
      if (order == 1 || !border_vertex[adj.neighbours[m]] || on_border(m)) {
        column.push_back(adj.neighbours[m]);
        const double w = adj.weight.empty() ? 1.0 : adj.weight[m];
        column_weight.emplace_back(adj.neighbours[m], order == 2 && border_vertex[adj.neighbours[m]] ? 1.0 : w);
      }
    std::sort(column.begin(), column.end());
    std::sort(column_weight.begin(), column_weight.end());
    for (std::size_t k : column) {
      const double w_ki =
          k == i ? 0.0 : std::lower_bound(column_weight.begin(), column_weight.end(), std::pair(k, -HUGE_VAL))->second;
      if (order == 1) {
        add(k, k == i ? (adj.weight.empty() ? degree(i) : diagonal_all(i)) : -w_ki);
        continue;
      }
      // Row k of M⁻¹ K, times K_ki.
      const double K_ki = k == i ? diagonal[i] : -w_ki;
      const double d_k = 1.0 / row_count[k];
      add(k, (diagonal[k] * d_k) * K_ki);
      for (std::size_t m = adj.offsets[k]; m < adj.offsets[k + 1]; ++m)
        if (!border_vertex[k] || on_border(m)) add(adj.neighbours[m], (-weight(k, m) * d_k) * K_ki);
    }
    if (scale != 1)
      for (std::size_t j : touched) value[j] *= scale;
    if (extra)
      for (Sparse::InnerIterator it(*extra, static_cast<Eigen::Index>(i)); it; ++it)
        add(static_cast<std::size_t>(it.row()), it.value());
    std::sort(touched.begin(), touched.end());
    Q.startVec(static_cast<Eigen::Index>(i));
    for (std::size_t j : touched) {
      Q.insertBack(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) = value[j];
      seen[j] = false;
    }
  }
  Q.finalize();
  return Q;
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
                                                Displacement_report* report,
                                                const std::vector<Vector_3>* target_laplacian) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  check_sizes(n, constrained, given);
  if (order != 1 && order != 2) throw Invalid_input("displacement: order must be 1 or 2, not " + std::to_string(order));
  if (target_laplacian && (order != 2 || target_laplacian->size() != n))
    throw Invalid_input("displacement: a target Laplacian needs order 2 and one vector per vertex (" +
                        std::to_string(target_laplacian->size()) + " for " + std::to_string(n) + ")");
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
  const Sparse Q = energy_matrix(adj, order, 1.0);

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
  if (target_laplacian) {
    // The energy (K d − t)ᵀ M⁻¹ (K d − t) adds Kᵀ M⁻¹ t to the right-hand side.
    const Laplacian_rows rows(adj);
    std::vector<Vector_3> b(n, Vector_3(0, 0, 0));
    for (std::size_t k = 0; k < n; ++k) {
      if (rows.degree(k) == 0) continue;
      const Vector_3 y = (*target_laplacian)[k] / rows.mass[k];
      b[k] = b[k] + rows.diagonal[k] * y;
      for (std::size_t m = adj.offsets[k]; m < adj.offsets[k + 1]; ++m)
        if (rows.in_row(k, m)) b[adj.neighbours[m]] = b[adj.neighbours[m]] - rows.weight(k, m) * y;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (free_index[i] >= 0) {
        if (!(std::isfinite(b[i].x()) && std::isfinite(b[i].y()) && std::isfinite(b[i].z())))
          throw Invalid_input("displacement: the target Laplacian near vertex " + std::to_string(i) + " is not finite");
        rhs(free_index[i], 0) += b[i].x(), rhs(free_index[i], 1) += b[i].y(), rhs(free_index[i], 2) += b[i].z();
      }
  }
  // Symmetric positive definite: every part of the mesh has a held vertex.
  const Eigen::MatrixXd x = solve_definite(A, rhs, "system");
  r.nonzeros = static_cast<std::size_t>(A.nonZeros());
  for (std::size_t i = 0; i < n; ++i)
    if (free_index[i] >= 0) d[i] = Vector_3(x(free_index[i], 0), x(free_index[i], 1), x(free_index[i], 2));
  if (report) *report = r;
  return d;
}

void set_cotangent_weights(Vertex_adjacency& adj, const std::vector<Point_3>& points,
                           const std::vector<std::array<std::size_t, 3>>& triangles) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  if (points.size() != n)
    throw Invalid_input("displacement: " + std::to_string(points.size()) + " points for " + std::to_string(n) + " vertices");
  // The position of neighbour j in i's row.
  auto position = [&](std::size_t t, std::size_t i, std::size_t j) {
    for (std::size_t m = adj.offsets[i]; m < adj.offsets[i + 1]; ++m)
      if (adj.neighbours[m] == j) return m;
    throw Invalid_input("displacement: triangle " + std::to_string(t) + " has the edge " + std::to_string(i) + "-" +
                        std::to_string(j) + ", which is not in the adjacency");
  };
  constexpr double cot_bound = 5.6712818196177099;  // cot(10°)
  constexpr double sine_floor = 0.017452406437283512;  // sin(1°): no division by a zero area
  constexpr double least_weight = 0.05;
  const double half_sqrt3 = std::sqrt(3.0) / 2;  // (cot 60° + cot 60°) · √3/2 = 1
  std::vector<double> cot_sum(adj.neighbours.size(), 0.0), area(n, 0.0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& c = triangles[t];
    for (std::size_t i : c)
      if (i >= n) throw Invalid_input("displacement: triangle " + std::to_string(t) + " has corner " + std::to_string(i) +
                                      " of " + std::to_string(n) + " vertices");
    const Vector_3 normal = CGAL::cross_product(points[c[1]] - points[c[0]], points[c[2]] - points[c[0]]);
    const double doubled_area = std::sqrt(normal.squared_length());
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t o = c[k], i = c[(k + 1) % 3], j = c[(k + 2) % 3];
      area[o] += doubled_area / 6;
      // The angle at o, opposite edge ij: cos / sin, bounded by cot(10°) in magnitude.
      const Vector_3 u = points[i] - points[o], v = points[j] - points[o];
      const double uv = std::sqrt(u.squared_length() * v.squared_length());
      const double cot = uv > 0 ? std::clamp((u * v) / std::max(doubled_area, sine_floor * uv), -cot_bound, cot_bound) : 0;
      cot_sum[position(t, i, j)] += cot;
      cot_sum[position(t, j, i)] += cot;
    }
  }
  adj.weight.resize(adj.neighbours.size());
  for (std::size_t m = 0; m < cot_sum.size(); ++m) adj.weight[m] = std::max(half_sqrt3 * cot_sum[m], least_weight);
  // The mean over the vertices on a face: a vertex of no face (unused) changes no other mass.
  const std::size_t used = static_cast<std::size_t>(std::count_if(area.begin(), area.end(), [](double a) { return a > 0; }));
  const double mean_area = used > 0 ? std::accumulate(area.begin(), area.end(), 0.0) / static_cast<double>(used) : 0;
  adj.mass.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    adj.mass[i] = mean_area > 0 ? 6 * std::max(area[i], 1e-3 * mean_area) / mean_area : 6;
}

namespace {

// Each vertex's area (a third of its faces') and unit normal (its faces' normals weighted by
// area; zero when they cancel).
void areas_and_normals(const std::vector<Point_3>& points, const std::vector<std::array<std::size_t, 3>>& triangles,
                       std::vector<double>& area, std::vector<Vector_3>& normal) {
  area.assign(points.size(), 0.0);
  normal.assign(points.size(), Vector_3(0, 0, 0));
  for (const auto& c : triangles) {
    const Vector_3 nf = CGAL::cross_product(points[c[1]] - points[c[0]], points[c[2]] - points[c[0]]);
    const double a = std::sqrt(nf.squared_length()) / 6;
    for (std::size_t i : c) area[i] += a, normal[i] = normal[i] + nf;
  }
  for (Vector_3& v : normal) {
    const double l = std::sqrt(v.squared_length());
    v = l > 0 ? v / l : Vector_3(0, 0, 0);
  }
}

}  // namespace

std::vector<Vector_3> laplacian_of(const Vertex_adjacency& adj, const std::vector<Point_3>& points) {
  const std::size_t n = adj.size();
  if (points.size() != n)
    throw Invalid_input("displacement: " + std::to_string(points.size()) + " points for " + std::to_string(n) + " vertices");
  const Laplacian_rows rows(adj);
  std::vector<Vector_3> out(n, Vector_3(0, 0, 0));
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t m = adj.offsets[k]; m < adj.offsets[k + 1]; ++m)
      if (rows.in_row(k, m)) out[k] = out[k] + rows.weight(k, m) * (points[k] - points[adj.neighbours[m]]);
  return out;
}

Vertex_adjacency triangle_adjacency(std::size_t n, const std::vector<std::array<std::size_t, 3>>& triangles) {
  std::vector<std::vector<std::size_t>> around(n);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t i = triangles[t][k], j = triangles[t][(k + 1) % 3];
      if (i >= n || j >= n)
        throw Invalid_input("displacement: triangle " + std::to_string(t) + " has a corner out of " + std::to_string(n) + " vertices");
      around[i].push_back(j), around[j].push_back(i);
    }
  Vertex_adjacency adj;
  for (auto& a : around) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    adj.neighbours.insert(adj.neighbours.end(), a.begin(), a.end());
    adj.offsets.push_back(adj.neighbours.size());
  }
  return adj;
}

std::vector<double> normal_bending(const std::vector<Point_3>& points, const std::vector<std::array<std::size_t, 3>>& triangles) {
  internal::Fp_trap_scope traps;
  const std::size_t n = points.size();
  Vertex_adjacency adj = triangle_adjacency(n, triangles);
  set_cotangent_weights(adj, points, triangles);
  const std::vector<Vector_3> lap = laplacian_of(adj, points);
  std::vector<double> area;
  std::vector<Vector_3> normal;
  areas_and_normals(points, triangles, area, normal);
  std::vector<double> bending(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (area[i] > 0) bending[i] = (lap[i] * normal[i]) / area[i];
  return bending;
}

std::vector<Vector_3> bent_laplacian(const std::vector<double>& bending, const std::vector<Point_3>& points,
                                     const std::vector<std::array<std::size_t, 3>>& triangles) {
  if (bending.size() != points.size())
    throw Invalid_input("displacement: " + std::to_string(bending.size()) + " bending values for " +
                        std::to_string(points.size()) + " points");
  std::vector<double> area;
  std::vector<Vector_3> normal;
  areas_and_normals(points, triangles, area, normal);
  std::vector<Vector_3> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = (bending[i] * area[i]) * normal[i];
  return out;
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

namespace {

// fit_displacements' system A d = rhs on every vertex: stiffness times the thin-plate energy plus
// the constraints' least-squares term, and an identity row for each vertex of a part of the mesh
// that no constraint touches (it keeps a zero displacement). `held` gets those vertices.
void soft_system(const Vertex_adjacency& adj, const std::vector<Soft_displacement>& constraints, double stiffness,
                 Sparse& A, Eigen::MatrixXd& rhs, std::vector<bool>& held) {
  const std::size_t n = adj.size();
  if (!std::isfinite(stiffness) || !(stiffness > 0))
    throw Invalid_input("displacement: the stiffness must be positive, not " + internal::format_number(stiffness));
  const auto N = static_cast<Eigen::Index>(n);
  std::vector<Eigen::Triplet<double>> t;
  rhs = Eigen::MatrixXd::Zero(N, 3);
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
  held.assign(n, false);
  for (std::size_t i = 0; i < n; ++i)
    if (!reached[i]) held[i] = true, t.emplace_back(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i), 1.0);
  Sparse data(N, N);
  data.setFromTriplets(t.begin(), t.end());
  A = energy_matrix(adj, 2, stiffness, &data);
}

// A coarse space (a public struct a caller may fill) that fits a mesh of n vertices: rows in
// order, every entry's node in range, every weight finite.
void check_coarse_space(const Coarse_space& cs, std::size_t n) {
  const std::string what = "displacement: a coarse space ";
  if (cs.offsets.size() != n + 1)
    throw Invalid_input(what + "of " + std::to_string(cs.offsets.size() - 1) + " vertices for a mesh of " + std::to_string(n));
  if (cs.offsets.front() != 0 || !std::is_sorted(cs.offsets.begin(), cs.offsets.end()) ||
      cs.offsets.back() != cs.node.size() || cs.weight.size() != cs.node.size())
    throw Invalid_input(what + "whose rows do not match its " + std::to_string(cs.node.size()) + " entries");
  for (std::size_t k = 0; k < cs.node.size(); ++k)
    if (cs.node[k] >= cs.nodes || !std::isfinite(cs.weight[k]))
      throw Invalid_input(what + "with entry " + std::to_string(k) + " out of its " + std::to_string(cs.nodes) +
                          " nodes or not finite");
}

std::vector<Vector_3> to_vectors(const Eigen::MatrixXd& x) {
  std::vector<Vector_3> d(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index i = 0; i < x.rows(); ++i) d[static_cast<std::size_t>(i)] = Vector_3(x(i, 0), x(i, 1), x(i, 2));
  return d;
}

// The aggregates of coarse_space: in vertex order, a vertex whose neighbours are all unclaimed
// claims every unclaimed vertex up to `rings` edges from it (a breadth-first search through
// unclaimed vertices); every vertex left joins the aggregate of the nearest claimed vertex (a
// breadth-first search from the claimed ones). Each aggregate is connected. Returns each vertex's
// aggregate; `seed` gets each aggregate's seed vertex.
std::vector<std::size_t> aggregates(const Vertex_adjacency& adj, std::size_t rings, std::vector<std::size_t>& seed) {
  const std::size_t n = adj.size();
  constexpr std::size_t none = SIZE_MAX;
  std::vector<std::size_t> of(n, none), ring, next;
  seed.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (of[i] != none) continue;
    bool ring_free = true;
    for (std::size_t k = adj.offsets[i]; k < adj.offsets[i + 1] && ring_free; ++k) ring_free = of[adj.neighbours[k]] == none;
    if (!ring_free) continue;
    const std::size_t a = seed.size();
    seed.push_back(i);
    of[i] = a;
    ring.assign(1, i);
    for (std::size_t r = 0; r < rings && !ring.empty(); ++r) {
      next.clear();
      for (std::size_t v : ring)
        for (std::size_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k)
          if (of[adj.neighbours[k]] == none) of[adj.neighbours[k]] = a, next.push_back(adj.neighbours[k]);
      ring.swap(next);
    }
  }
  // Every vertex left has a claimed vertex in its part of the mesh (a vertex with no claimed
  // neighbour claims itself above).
  ring.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (of[i] != none) ring.push_back(i);
  while (!ring.empty()) {
    next.clear();
    for (std::size_t v : ring)
      for (std::size_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k)
        if (of[adj.neighbours[k]] == none) of[adj.neighbours[k]] = of[v], next.push_back(adj.neighbours[k]);
    ring.swap(next);
  }
  return of;
}

}  // namespace

Coarse_space coarse_space(const Vertex_adjacency& adj, const std::vector<Point_3>& points,
                          const std::vector<Vector_3>& normals, std::size_t rings) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  if (points.size() != n || normals.size() != n)
    throw Invalid_input("displacement: " + std::to_string(n) + " vertices but " + std::to_string(points.size()) +
                        " points and " + std::to_string(normals.size()) + " normals");
  if (rings == 0) throw Invalid_input("displacement: a coarse space's aggregates need at least one ring");
  std::vector<std::size_t> seed;
  const std::vector<std::size_t> of = aggregates(adj, rings, seed);
  const std::size_t m = seed.size();
  // The nodes beside each node (aggregates joined by an edge), itself first.
  std::vector<std::vector<std::size_t>> beside(m);
  for (std::size_t a = 0; a < m; ++a) beside[a].push_back(a);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = adj.offsets[i]; k < adj.offsets[i + 1]; ++k) {
      const std::size_t a = of[i], b = of[adj.neighbours[k]];
      if (a != b) beside[a].push_back(b);
    }
  for (auto& b : beside) std::sort(b.begin() + 1, b.end()), b.erase(std::unique(b.begin() + 1, b.end()), b.end());
  // Each node's reach R: its distance to the farthest node beside it, and more than its distance
  // to any vertex of its aggregate (so that each vertex's own node weighs on it). (Reaching the
  // vertices of the aggregates beside instead smooths more and resolves less: on the bench/scale
  // cases the fit ended 0.61 % and 0.83 % from the truth instead of 0.51 % and 0.53 %.)
  std::vector<double> reach2(m, 0);
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t k = 1; k < beside[a].size(); ++k)
      reach2[a] = std::max(reach2[a], CGAL::squared_distance(points[seed[a]], points[seed[beside[a][k]]]));
  for (std::size_t i = 0; i < n; ++i)
    reach2[of[i]] = std::max(reach2[of[i]], 1.21 * CGAL::squared_distance(points[seed[of[i]]], points[i]));
  // The nodes a vertex of each aggregate may be reached by: those up to two aggregates away.
  std::vector<std::vector<std::size_t>> candidates(m);
  for (std::size_t a = 0; a < m; ++a) {
    for (std::size_t b : beside[a]) candidates[a].insert(candidates[a].end(), beside[b].begin(), beside[b].end());
    std::sort(candidates[a].begin(), candidates[a].end());
    candidates[a].erase(std::unique(candidates[a].begin(), candidates[a].end()), candidates[a].end());
  }

  Coarse_space cs;
  cs.nodes = m;
  cs.seed = seed;
  cs.offsets.reserve(n + 1);
  std::vector<std::size_t> near;
  std::vector<double> rho;
  std::vector<Eigen::Vector3d> basis;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = of[i];
    const Point_3& x = points[i];
    // Moving least squares with the basis 1, s, t (s, t along the tangent plane, in units of the
    // own node's reach): weight_j = rho_j e₁ᵀ M⁻¹ p_j, M = Σ rho_j p_j p_jᵀ; linear along the
    // plane is reproduced. Where M is nearly singular (fewer than three nodes reach the vertex,
    // or they lie on a line: at a border, where aggregates are cut), the reaches are widened for
    // this vertex, up to three times; then, or when the normal is unusable, the weights are
    // rho_j / Σ rho.
    const Vector_3& nv = normals[i];
    const double nn = nv.squared_length();
    const bool tangent = std::isfinite(nn) && nn > 0;
    Vector_3 t1(1, 0, 0), t2(0, 1, 0);
    if (tangent) {
      const Vector_3 nu = nv / std::sqrt(nn);
      t1 = CGAL::cross_product(nu, std::abs(nu.x()) < 0.6 ? Vector_3(1, 0, 0) : Vector_3(0, 1, 0));
      t1 = t1 / std::sqrt(t1.squared_length());
      t2 = CGAL::cross_product(nu, t1);
    }
    const double unit = 1 / std::sqrt(reach2[a] > 0 ? reach2[a] : 1);
    bool linear = false;
    Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
    for (double widen : {1.0, 2.25, 4.0, 9.0}) {  // the reaches × 1, 1.5, 2, 3
      near.clear(), rho.clear(), basis.clear();
      for (std::size_t b : candidates[a]) {
        const double r = reach2[b] > 0 ? CGAL::squared_distance(x, points[seed[b]]) / (widen * reach2[b]) : 0;
        if (r < 1) near.push_back(b), rho.push_back((1 - r) * (1 - r) * (1 - r));
      }
      if (!tangent) break;
      if (near.size() < 3) continue;
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (std::size_t k = 0; k < near.size(); ++k) {
        const Vector_3 o = points[seed[near[k]]] - x;
        basis.emplace_back(1, unit * (o * t1), unit * (o * t2));
        M += rho[k] * basis.back() * basis.back().transpose();
      }
      const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(M, Eigen::EigenvaluesOnly).eigenvalues();
      linear = ev(0) > 1e-6 * ev(2);
      if (linear) {
        e1 = M.inverse().col(0);  // M⁻¹ e₁ (M symmetric)
        break;
      }
    }
    // (Its own node reaches every vertex: `near` is never empty.)
    double total = 0;
    for (double r : rho) total += r;
    for (std::size_t k = 0; k < near.size(); ++k) {
      const double w = linear ? rho[k] * e1.dot(basis[k]) : rho[k] / total;
      if (w == 0) continue;
      cs.node.push_back(near[k]);
      cs.weight.push_back(w);
    }
    cs.offsets.push_back(cs.node.size());
  }
  return cs;
}

std::vector<Vector_3> fit_displacements(const Vertex_adjacency& adj, const std::vector<Soft_displacement>& constraints,
                                        double stiffness, const Coarse_space* coarse) {
  internal::Fp_trap_scope traps;
  const std::size_t n = adj.size();
  if (coarse) check_coarse_space(*coarse, n);
  Sparse A;
  Eigen::MatrixXd rhs;
  std::vector<bool> held;
  soft_system(adj, constraints, stiffness, A, rhs, held);
  if (!coarse) return to_vectors(solve_definite(A, rhs, "fitting system"));
  Sparse P(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(coarse->nodes));
  {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(coarse->node.size());
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = coarse->offsets[i]; k < coarse->offsets[i + 1]; ++k)
        t.emplace_back(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(coarse->node[k]), coarse->weight[k]);
    P.setFromTriplets(t.begin(), t.end());
  }
  const Sparse Pt = P.transpose();
  const Sparse Ac = Pt * Sparse(A * P);
  Eigen::MatrixXd x;
  try {
    x = P * solve_definite(Ac, Pt * rhs, "coarse fitting system");
  } catch (const Numerical_error&) {
    x = solve_definite(A, rhs, "fitting system");
  }
  for (std::size_t i = 0; i < n; ++i)
    if (held[i]) x.row(static_cast<Eigen::Index>(i)).setZero();
  return to_vectors(x);
}

}  // namespace meshfit
