// The compiled core of stage 3 (smooth.h): the flows of thesis ch. 4 on flat arrays.
//
// Every iteration is a Jacobi step over vertices (new positions from the old ones only), so the
// per-vertex loops run in parallel and the result does not depend on the number of threads. The
// connectivity is turned once into compressed rows (vertex → neighbours with their edge, vertex
// → incident faces, face → faces across its edges) so that a step reads memory linearly; that is
// what makes a step cost tens of nanoseconds per vertex.
//
// Guards (so that no value is ever non-finite, and no face flips):
//   - cotangents (eq. 4.8) are computed as cos/sin with the sine bounded below by sin(1°) times
//     the product of the two edge lengths, i.e. |cot| ≤ cot(1°) ≈ 57.3: a needle or a zero-area
//     face has bounded weights ("clamped" in the report);
//   - the mean-curvature step of a vertex is λ·h̄²·H (h̄ the mean edge length of the mesh at the
//     call, so λ is dimensionless), but never more than the step 4A/Σ|w| that moves the vertex
//     to its cotangent-weighted neighbour average: the explicit scheme stays stable on small
//     faces and a vertex whose faces have no area (A = 0) or whose weights all vanish stays put;
//   - inverse-distance weights (eq. 4.4) use max(|p − q|, 1e-6·h̄);
//   - after each step, every face whose normal would turn by more than 90° (floating-point
//     filter, exact orientation test in the plane of the face when the filter is unsure)
//     halves the step of its free corners, up to 4 times, after which those corners do not
//     move in that iteration. Faces of zero area before the step have no normal and are not
//     judged.
//
// The reference surfaces of the modified flows (eq. 4.9 and 4.11 project the step onto "the face
// closest to p^k" and put p^{k+1} on that face): a vertex p^k lies on all of its incident faces
// of the reference surface, so "the closest face" is decided by where the step goes. meshfit
// walks from a face of the reference surface holding the vertex towards p^k + step: on the
// current face, it takes the barycentric coordinates of the point projected onto the face's
// plane; when they are all non-negative the projection is p^{k+1} (the intersection of n with
// the face, as in figs. 4.11 and 4.12); otherwise it crosses the edge of the most negative
// coordinate, unless that edge is on the boundary or a curve, or crossing it goes back to the
// face it came from (a ridge), or 16 faces were visited: then p^{k+1} is the closest point of
// the current face. p^{k+1} is therefore always on the reference surface, in the same region,
// and reached through faces that p^k's step crosses. This is a local search of O(1) per vertex
// instead of a global closest-point query: for the modified mean-curvature flow the reference
// changes every iteration (an AABB tree would be rebuilt each time), and for the modified
// Laplacian flow a tree query costs more than the rest of the step; the walk gives the same face
// as the closest-point query whenever the step stays within the faces around the vertex, which
// the step bound above guarantees up to the walk's corner cases (ridges, where the closest
// point of the last face is taken, which is the closest point of the two faces).
#include <meshfit/flip.h>
#include <meshfit/smooth.h>
#include <meshfit/internal/unit_scale.h>

#include "fp_traps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

namespace meshfit {
namespace internal {
namespace {

constexpr std::uint32_t no_face = std::numeric_limits<std::uint32_t>::max();
constexpr int max_halvings = 4;
constexpr int max_walk_faces = 16;
// sin(1°): cotangents are bounded by cot(1°) ≈ 57.3 (needles, zero-area faces).
constexpr double sin_one_degree = 0.017452406437283512;
// The flip guard's needle threshold on |n| / (longest edge)² (about 1.7°'s sine, halved).
constexpr double needle_shape = 0.015;

struct V3 {
  double x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline V3 load(const double* p, std::size_t i) { return {p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
inline void store(double* p, std::size_t i, V3 v) {
  p[3 * i] = v.x;
  p[3 * i + 1] = v.y;
  p[3 * i + 2] = v.z;
}

/// Half-edges a → b (opposite corner k of face f, numbered 3·f + k), listed by their source vertex
/// in compressed rows; the twin b → a is found in b's short list. Linear time: sorting the 3·nf
/// half-edges instead cost as much as five smoothing iterations.
struct Outgoing_half_edges {
  static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> start, target, half;

  Outgoing_half_edges(const Smoothing_arrays& m, std::size_t n) : start(n + 1, 0) {
    const std::size_t nf = m.triangles.size();
    for (const auto& t : m.triangles)
      for (std::uint32_t v : t) ++start[v + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    target.resize(3 * nf);
    half.resize(3 * nf);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t a = m.triangles[f][(k + 1) % 3], b = m.triangles[f][(k + 2) % 3];
        target[fill[a]] = b;
        half[fill[a]++] = std::uint32_t(3 * f + k);
      }
  }

  /// The half-edge b → a, or `none`.
  std::uint32_t twin(std::uint32_t a, std::uint32_t b) const {
    std::uint32_t found = none, count = 0;
    for (std::uint32_t j = start[b]; j < start[b + 1]; ++j)
      if (target[j] == a) {
        found = half[j];
        ++count;
      }
    return count == 1 ? found : none;  // more than one: a non-manifold edge, no neighbour
  }
};

/// Connectivity in compressed rows, built once per call of run_flows (its flows share it).
struct Topology {
  std::size_t n = 0, nf = 0;
  std::vector<std::array<std::uint32_t, 2>> edge_vertices;
  std::vector<std::array<std::uint32_t, 3>> face_edge;  // edge opposite corner k
  std::vector<std::array<std::uint32_t, 3>> face_adj;   // face across that edge; no_face at boundary/curve
  std::vector<std::array<std::uint32_t, 3>> face_nbr;   // face across that edge, curves too; no_face at boundary
  std::vector<std::uint32_t> nbr_start, nbr, nbr_edge;  // vertex → neighbour, edge
  std::vector<std::uint32_t> vf_start, vf;              // vertex → incident faces

  Topology(const Smoothing_arrays& m) : n(m.fixed.size()), nf(m.triangles.size()) {
    const Outgoing_half_edges out(m, n);
    number_edges(out, m.constrained_edges);
    build_neighbour_rows();
    build_incident_face_rows(m, out.start);
  }

  /// The mean length of the edges at `points`.
  double mean_edge_length(const std::vector<double>& points) const {
    double sum = 0;
    for (const auto& e : edge_vertices) {
      const V3 d = load(points.data(), e[0]) - load(points.data(), e[1]);
      sum += std::sqrt(dot(d, d));
    }
    return edge_vertices.empty() ? 0 : sum / double(edge_vertices.size());
  }

 private:
  // Numbers the edges (edge_vertices) and gives each face its edges and its neighbours across
  // them (face_edge, face_nbr, face_adj).
  void number_edges(const Outgoing_half_edges& out, std::vector<std::array<std::uint32_t, 2>> constrained) {
    for (auto& e : constrained)
      if (e[0] > e[1]) std::swap(e[0], e[1]);
    std::sort(constrained.begin(), constrained.end());
    face_edge.assign(nf, {0, 0, 0});
    face_adj.assign(nf, {no_face, no_face, no_face});
    face_nbr.assign(nf, {no_face, no_face, no_face});
    for (std::uint32_t a = 0; a < n; ++a)
      for (std::uint32_t j = out.start[a]; j < out.start[a + 1]; ++j) {
        const std::uint32_t b = out.target[j], h = out.half[j];
        const std::uint32_t twin = out.twin(a, b);
        if (twin != Outgoing_half_edges::none && a > b) continue;  // the twin's owner numbers the edge
        const std::uint32_t e = std::uint32_t(edge_vertices.size());
        edge_vertices.push_back({std::min(a, b), std::max(a, b)});
        face_edge[h / 3][h % 3] = e;
        if (twin == Outgoing_half_edges::none) continue;
        face_edge[twin / 3][twin % 3] = e;
        face_nbr[h / 3][h % 3] = twin / 3;
        face_nbr[twin / 3][twin % 3] = h / 3;
        // Faces are adjacent across a manifold edge that is not a curve: the projection walks
        // stay inside a region and never leave the surface through its rim.
        if (!constrained.empty() &&
            std::binary_search(constrained.begin(), constrained.end(), edge_vertices.back()))
          continue;
        face_adj[h / 3][h % 3] = twin / 3;
        face_adj[twin / 3][twin % 3] = h / 3;
      }
  }

  // Vertex → neighbour and edge rows (nbr_start, nbr, nbr_edge), from edge_vertices.
  void build_neighbour_rows() {
    nbr_start.assign(n + 1, 0);
    for (const auto& e : edge_vertices) {
      ++nbr_start[e[0] + 1];
      ++nbr_start[e[1] + 1];
    }
    std::partial_sum(nbr_start.begin(), nbr_start.end(), nbr_start.begin());
    nbr.resize(nbr_start[n]);
    nbr_edge.resize(nbr_start[n]);
    std::vector<std::uint32_t> fill(nbr_start.begin(), nbr_start.end() - 1);
    for (std::size_t e = 0; e < edge_vertices.size(); ++e) {
      const auto [a, b] = edge_vertices[e];
      nbr[fill[a]] = b;
      nbr_edge[fill[a]++] = std::uint32_t(e);
      nbr[fill[b]] = a;
      nbr_edge[fill[b]++] = std::uint32_t(e);
    }
  }

  // Vertex → incident face rows (vf_start, vf). A vertex has as many incident faces as outgoing
  // half-edges: the rows start where Outgoing_half_edges's do.
  void build_incident_face_rows(const Smoothing_arrays& m, const std::vector<std::uint32_t>& out_start) {
    vf_start = out_start;
    vf.resize(vf_start[n]);
    std::vector<std::uint32_t> fill(vf_start.begin(), vf_start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (std::uint32_t v : m.triangles[f]) vf[fill[v]++] = std::uint32_t(f);
  }
};

/// The closest point of segment ab to p (a when the segment has no length).
V3 closest_on_segment(V3 a, V3 b, V3 p) {
  const V3 ab = b - a;
  const double l2 = dot(ab, ab);
  if (!(l2 > 0)) return a;
  const double t = std::min(1.0, std::max(0.0, dot(p - a, ab) / l2));
  return a + t * ab;
}

/// A triangle's normal and whether it is too thin to have a plane we trust.
inline bool has_plane(V3 a, V3 b, V3 c, V3& n, double& nn) {
  n = cross(b - a, c - a);
  nn = dot(n, n);
  const double e2 = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
  // |n|² ≤ 1e-24 e⁴: the largest angle's sine is below about 1e-12, the plane is noise.
  return nn > 1e-24 * e2 * e2;
}

/// The closest point of triangle abc to p.
V3 closest_on_triangle(V3 a, V3 b, V3 c, V3 p) {
  V3 n;
  double nn;
  if (has_plane(a, b, c, n, nn)) {
    const V3 q = p - (dot(p - a, n) / nn) * n;
    if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 && dot(cross(a - c, q - c), n) >= 0)
      return q;
  }
  // Outside (or no plane): the closest point is on an edge.
  const V3 cand[3] = {closest_on_segment(a, b, p), closest_on_segment(b, c, p), closest_on_segment(c, a, p)};
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (dot(cand[k] - p, cand[k] - p) < dot(cand[best] - p, cand[best] - p)) best = k;
  return cand[best];
}

/// has_plane of every face of a surface that does not change during a flow (the modified
/// Laplacian's reference): computed once instead of at every step of every walk.
struct Reference_planes {
  std::vector<double> normal;          // 3 per face
  std::vector<unsigned char> trusted;  // has_plane's answer

  Reference_planes(const double* ref, const Smoothing_arrays& m) : normal(3 * m.triangles.size()), trusted(m.triangles.size()) {
    const std::ptrdiff_t snf = std::ptrdiff_t(m.triangles.size());
#pragma omp parallel for schedule(static) if (snf >= 100000)
    for (std::ptrdiff_t sf = 0; sf < snf; ++sf) {
      const std::size_t f = std::size_t(sf);
      const auto& tri = m.triangles[f];
      V3 n;
      double nn;
      trusted[f] = has_plane(load(ref, tri[0]), load(ref, tri[1]), load(ref, tri[2]), n, nn);
      store(normal.data(), f, n);
    }
  }
};

/// The walk of smooth.h: from face f of the reference surface towards p; returns the landing
/// point, sets f to the landing face and `clamped` when it ended at a face's closest point.
/// `planes`, when given, holds every face's has_plane of ref (Reference_planes).
V3 walk(const double* ref, const Reference_planes* planes, const Smoothing_arrays& m, const Topology& t, std::uint32_t& f,
        V3 p, bool& clamped) {
  std::uint32_t prev = no_face;
  for (int step = 0; step < max_walk_faces; ++step) {
    const auto& tri = m.triangles[f];
    const V3 v[3] = {load(ref, tri[0]), load(ref, tri[1]), load(ref, tri[2])};
    V3 n;
    double nn;
    if (planes) {
      if (!planes->trusted[f]) break;
      n = load(planes->normal.data(), f);
      nn = dot(n, n);
    } else if (!has_plane(v[0], v[1], v[2], n, nn)) {
      break;
    }
    const V3 q = p - (dot(p - v[0], n) / nn) * n;
    int kmin = 0;
    double lmin = 0;
    for (int k = 0; k < 3; ++k) {
      // Unnormalised barycentric coordinate of corner k (same sign as the true one).
      const double l = dot(cross(v[(k + 2) % 3] - v[(k + 1) % 3], q - v[(k + 1) % 3]), n);
      if (k == 0 || l < lmin) {
        lmin = l;
        kmin = k;
      }
    }
    if (lmin >= 0) {
      clamped = false;
      return q;
    }
    const std::uint32_t g = t.face_adj[f][kmin];
    if (g == no_face || g == prev) break;
    prev = f;
    f = g;
  }
  clamped = true;
  const auto& tri = m.triangles[f];
  return closest_on_triangle(load(ref, tri[0]), load(ref, tri[1]), load(ref, tri[2]), p);
}

bool finite(V3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

void check_smoothing_input(const Smoothing_arrays& m) {
  const std::size_t n = m.fixed.size();
  if (m.points.size() != 3 * n) throw Invalid_input("smooth: point array and vertex count disagree");
  for (std::size_t i = 0; i < n; ++i)
    if (!finite(load(m.points.data(), i)))
      throw Invalid_input("smooth: vertex " + std::to_string(i) + " has a non-finite coordinate");
  if (!m.reference_points.empty()) {
    if (m.reference_points.size() != 3 * n) throw Invalid_input("smooth: reference_points has the wrong size");
    for (std::size_t i = 0; i < n; ++i)
      if (!finite(load(m.reference_points.data(), i)))
        throw Invalid_input("smooth: reference point " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    if (t[0] >= n || t[1] >= n || t[2] >= n)
      throw Invalid_input("smooth: face " + std::to_string(f) + " refers to a missing vertex");
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Invalid_input("smooth: face " + std::to_string(f) + " repeats a vertex");
  }
}

void fill_displacements(const std::vector<double>& before, const std::vector<double>& after, Smoothing_report& r) {
  const std::size_t n = before.size() / 3;
  double sum = 0, mx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const V3 d = load(after.data(), i) - load(before.data(), i);
    const double l = std::sqrt(dot(d, d));
    sum += l;
    mx = std::max(mx, l);
  }
  r.mean_displacement = n ? sum / double(n) : 0;
  r.max_displacement = mx;
}

namespace {

// The arrays a flow works in, kept from one flow of run_flows to the next: on this project's
// machines the first write to fresh memory costs more than the writes themselves (1 GB: 3 s
// against 0.08 s), and the arrays are as large as the mesh.
struct Flow_buffers {
  std::vector<double> p0, initial_normal, cur, next, disp, scale, face_area2, edge_w, next_normal, next_edge2;
  std::vector<std::array<double, 3>> face_cot;
  std::vector<std::uint32_t> home, landing, vertex_round, face_round;
  std::vector<unsigned char> walk_clamped, flipped;
  std::vector<int> halvings;
};

// One run of a flow (run_flows): the flow's constants, the state that iterations carry (in the
// arrays of a Flow_buffers, taken for the run and given back after it), and the parts of one
// iteration.
class Flow_run {
 public:
  Flow_run(Smoothing_arrays& m, const Flow_settings& s, Smoothing_report& report, const Topology& t, Flow_buffers& buffers)
      : m(m), s(s), report(report), t(t), buffers(buffers), n(t.n), nf(t.nf), sn(std::ptrdiff_t(n)), snf(std::ptrdiff_t(nf)),
        modified(s.kind == Flow_kind::modified_mean_curvature || s.kind == Flow_kind::modified_laplacian),
        curvature(s.kind == Flow_kind::mean_curvature || s.kind == Flow_kind::modified_mean_curvature),
        reference(m.reference_points.empty() ? p0 : m.reference_points),
        oriented(m.orientation_points.size() == m.points.size() ? m.orientation_points : p0),
        mean_edge(t.mean_edge_length(m.points)), tau(s.step * mean_edge * mean_edge), min_distance(1e-6 * mean_edge),
        parallel(n >= 50000) {
    swap_buffers();
    p0 = m.points;
    // The normals of the faces at the call (zero for a face of zero area), for the flip guard.
    initial_normal.resize(3 * nf);
    for (std::size_t f = 0; f < nf; ++f) {
      const auto& tri = m.triangles[f];
      const V3 a = load(oriented.data(), tri[0]), b = load(oriented.data(), tri[1]), c = load(oriented.data(), tri[2]);
      store(initial_normal.data(), f, cross(b - a, c - a));
    }
    if (s.kind == Flow_kind::modified_laplacian) ref_planes.emplace(reference.data(), m);
    // Each vertex's face of the reference surface (the modified Laplacian walks on from there).
    home.assign(n, no_face);
    for (std::size_t i = 0; i < n; ++i)
      if (t.vf_start[i] < t.vf_start[i + 1]) home[i] = t.vf[t.vf_start[i]];
    cur = m.points;
    next.assign(3 * n, 0.0);
    disp.assign(3 * n, 0.0);
    scale.assign(n, 0.0);
    landing.assign(n, 0);
    walk_clamped.assign(n, 0);
    flipped.assign(nf, 0);
    next_normal.assign(3 * nf, 0.0);
    next_edge2.assign(nf, 0.0);
    vertex_round.assign(n, 0);
    face_round.assign(nf, 0);
    halvings.assign(n, 0);
    if (curvature) {
      face_area2.assign(nf, 0.0);
      face_cot.assign(nf, {0.0, 0.0, 0.0});
      edge_w.assign(t.edge_vertices.size(), 0.0);
    }
  }
  Flow_run(const Flow_run&) = delete;
  Flow_run& operator=(const Flow_run&) = delete;
  ~Flow_run() { swap_buffers(); }

  void run() {
    for (std::size_t it = 0; it < s.iterations; ++it) {
      if (s.on_iteration && !s.on_iteration(s.progress_offset + it, s.progress_total ? s.progress_total : s.iterations))
        throw Cancelled("smooth");
      P = cur.data();
      const std::size_t clamped_cot = curvature ? cotangent_weights() : 0;
      compute_steps();
      // Candidate positions for the current scales; projected for the modified flows.
      ref = s.kind == Flow_kind::modified_laplacian ? reference.data() : P;
#pragma omp parallel for schedule(static) if (parallel)
      for (std::ptrdiff_t i = 0; i < sn; ++i) place(std::size_t(i));
      guard_flips();
      finish_iteration(it, clamped_cot);
      if (s.stop_below > 0 && report.last_step_max_displacement <= s.stop_below * mean_edge) break;
    }
    m.points = cur;
  }

 private:
  void swap_buffers() {
    Flow_buffers& b = buffers;
    p0.swap(b.p0), initial_normal.swap(b.initial_normal), cur.swap(b.cur), next.swap(b.next), disp.swap(b.disp);
    next_normal.swap(b.next_normal), next_edge2.swap(b.next_edge2);
    scale.swap(b.scale), face_area2.swap(b.face_area2), edge_w.swap(b.edge_w), face_cot.swap(b.face_cot);
    home.swap(b.home), landing.swap(b.landing), vertex_round.swap(b.vertex_round), face_round.swap(b.face_round);
    walk_clamped.swap(b.walk_clamped), flipped.swap(b.flipped), halvings.swap(b.halvings);
  }

  // The cotangent weight of every edge at P (face_area2, face_cot, edge_w); the number of angles
  // clamped.
  std::size_t cotangent_weights() {
    std::size_t clamped_cot = 0;
#pragma omp parallel for schedule(static) if (parallel) reduction(+ : clamped_cot)
    for (std::ptrdiff_t f = 0; f < snf; ++f) {
      const auto& tri = m.triangles[std::size_t(f)];
      const V3 v[3] = {load(P, tri[0]), load(P, tri[1]), load(P, tri[2])};
      const V3 nrm = cross(v[1] - v[0], v[2] - v[0]);
      const double area2 = std::sqrt(dot(nrm, nrm));  // |u × w| at every corner
      face_area2[std::size_t(f)] = area2;
      for (int k = 0; k < 3; ++k) {
        const V3 u = v[(k + 1) % 3] - v[k], w = v[(k + 2) % 3] - v[k];
        const double lower = sin_one_degree * std::sqrt(dot(u, u) * dot(w, w));
        double cot = 0;
        if (!(lower > 0)) {
          ++clamped_cot;  // a zero-length edge: the angle is undefined, weight 0
        } else if (area2 < lower) {
          ++clamped_cot;
          cot = dot(u, w) / lower;
        } else {
          cot = dot(u, w) / area2;
        }
        face_cot[std::size_t(f)][std::size_t(k)] = cot;
      }
    }
    std::fill(edge_w.begin(), edge_w.end(), 0.0);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) edge_w[t.face_edge[f][std::size_t(k)]] += face_cot[f][std::size_t(k)];
    return clamped_cot;
  }

  // The step of every free vertex, before projection and flip guard (disp); the scales reset.
  void compute_steps() {
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t si = 0; si < sn; ++si) {
      const std::size_t i = std::size_t(si);
      V3 d{0, 0, 0};
      const std::uint32_t b = t.nbr_start[i], e = t.nbr_start[i + 1];
      if (!m.fixed[i] && b < e) {
        const V3 p = load(P, i);
        if (curvature) {
          double area = 0;
          for (std::uint32_t k = t.vf_start[i]; k < t.vf_start[i + 1]; ++k) area += 0.5 * face_area2[t.vf[k]];
          V3 sum{0, 0, 0};
          double wabs = 0;
          for (std::uint32_t k = b; k < e; ++k) {
            const double w = edge_w[t.nbr_edge[k]];
            sum = sum + w * (load(P, t.nbr[k]) - p);
            wabs += std::abs(w);
          }
          // τ/(4A), but at most 1/Σ|w| (the full step to the weighted average): stable on small
          // faces, and no division by a zero area.
          if (area > 0 && wabs > 0) d = (tau * wabs <= 4 * area ? tau / (4 * area) : 1 / wabs) * sum;
        } else {
          V3 sum{0, 0, 0};
          double wsum = 0;
          for (std::uint32_t k = b; k < e; ++k) {
            const V3 q = load(P, t.nbr[k]);
            double w = 1;
            if (s.weights == Laplacian_weights::inverse_distance) {
              const double dist = std::sqrt(dot(q - p, q - p));
              w = dist > min_distance ? 1 / dist : min_distance > 0 ? 1 / min_distance : 1;
            }
            sum = sum + w * q;
            wsum += w;
          }
          if (s.kind == Flow_kind::laplacian && s.variant != Laplacian_variant::none) {
            // Eq. 4.5/4.6: the vertex itself is q_0 (weight: 1, or the mean neighbour weight).
            const double w0 = s.weights == Laplacian_weights::uniform ? 1 : wsum / double(e - b);
            const V3 avg = (1 / (wsum + w0)) * (sum + w0 * p);
            const V3 anchor = s.variant == Laplacian_variant::alpha_current ? p : load(p0.data(), i);
            d = (s.alpha * anchor + (1 - s.alpha) * avg) - p;
          } else {
            d = s.step * ((1 / wsum) * sum - p);
          }
        }
      }
      store(disp.data(), i, d);
      scale[i] = 1;
      halvings[i] = 0;
      vertex_round[i] = 0;
    }
    std::fill(face_round.begin(), face_round.end(), 0u);
  }

  // Vertex i's candidate position for its current scale (next), projected for the modified flows.
  void place(std::size_t i) {
    const V3 p = load(P, i);
    if (m.fixed[i]) {
      store(next.data(), i, p);
      return;
    }
    const V3 target = p + scale[i] * load(disp.data(), i);
    if (modified && home[i] != no_face && scale[i] > 0) {
      std::uint32_t f = home[i];
      bool c = false;
      store(next.data(), i, walk(ref, ref_planes ? &*ref_planes : nullptr, m, t, f, target, c));
      landing[i] = f;
      walk_clamped[i] = c;
    } else {
      store(next.data(), i, target);
      landing[i] = home[i];
      walk_clamped[i] = 0;
    }
  }

  // Flip guard: halve the steps of the free corners of faces that would flip or turn into
  // needles. After the first pass over all faces only the faces around the vertices whose
  // step changed are judged again; every round halves or cancels at least one step, and a
  // vertex's step is halved at most max_halvings times before it is cancelled, so the loop
  // ends. A face that stays flagged with all its corners still (impossible but for rounding)
  // changes nothing and is dropped.
  void guard_flips() {
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t f = 0; f < snf; ++f) shape_at_next(std::size_t(f));
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t f = 0; f < snf; ++f) flipped[std::size_t(f)] = judge(std::size_t(f));
    std::vector<std::uint32_t> flagged, changed, recheck;
    for (std::size_t f = 0; f < nf; ++f)
      if (flipped[f]) flagged.push_back(std::uint32_t(f));
    for (std::uint32_t round = 1; !flagged.empty(); ++round) {
      changed.clear();
      for (std::uint32_t f : flagged)
        for (std::uint32_t v : m.triangles[f]) {
          if (m.fixed[v] || scale[v] == 0 || vertex_round[v] == round) continue;
          vertex_round[v] = round;
          if (halvings[v] == 0) ++report.steps_reduced;
          if (++halvings[v] > max_halvings) {
            scale[v] = 0;
            ++report.steps_cancelled;
          } else {
            scale[v] *= 0.5;
          }
          changed.push_back(v);
        }
      if (changed.empty()) break;
#pragma omp parallel for schedule(static) if (parallel)
      for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(changed.size()); ++k) place(changed[std::size_t(k)]);
      recheck.clear();
      for (std::uint32_t v : changed)
        for (std::uint32_t k = t.vf_start[v]; k < t.vf_start[v + 1]; ++k)
          if (face_round[t.vf[k]] != round) {
            face_round[t.vf[k]] = round;
            recheck.push_back(t.vf[k]);
          }
      // Every face with a moved corner is in recheck: the neighbours' shapes judge reads are current.
#pragma omp parallel for schedule(static) if (parallel)
      for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(recheck.size()); ++k) shape_at_next(recheck[std::size_t(k)]);
#pragma omp parallel for schedule(static) if (parallel)
      for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(recheck.size()); ++k)
        flipped[recheck[std::size_t(k)]] = judge(recheck[std::size_t(k)]);
      flagged.clear();
      for (std::uint32_t f : recheck)
        if (flipped[f]) flagged.push_back(f);
    }
  }

  // Face f's normal and longest edge squared at `next` (next_normal, next_edge2), which judge reads
  // for the face and its neighbours: computed once per face rather than four times.
  void shape_at_next(std::size_t f) {
    const auto& tri = m.triangles[f];
    const V3 na = load(next.data(), tri[0]), nb = load(next.data(), tri[1]), nc = load(next.data(), tri[2]);
    store(next_normal.data(), f, cross(nb - na, nc - na));
    next_edge2[f] = std::max({dot(nb - na, nb - na), dot(nc - nb, nc - nb), dot(na - nc, na - nc)});
  }

  // Whether face f would flip or turn into a needle or fold over a neighbour at `next`
  // (shape_at_next of f and its neighbours made).
  bool judge(std::size_t f) const {
    const auto& tri = m.triangles[f];
    const V3 a = load(P, tri[0]), b = load(P, tri[1]), c = load(P, tri[2]);
    const V3 na = load(next.data(), tri[0]), nb = load(next.data(), tri[1]), nc = load(next.data(), tri[2]);
    const V3 n0 = cross(b - a, c - a), n1 = load(next_normal.data(), f);
    const double l0 = dot(n0, n0), l1 = dot(n1, n1);
    if (!(l0 > 0)) return false;  // a face of zero area has no normal to flip: not judged
    // A face must not turn into a needle either (that is how a flip starts, and a needle's
    // cotangents are clamped): its shape figure |n| / (longest edge)², about the sine of its
    // smallest angle, may not fall below needle_shape, or below what it was if it already was.
    // Compared squared and without division, so that an unmoved face always passes.
    const double e0 = std::max({dot(b - a, b - a), dot(c - b, c - b), dot(a - c, a - c)});
    const double e1 = next_edge2[f];
    if (!(l1 * (e0 * e0) >= std::min(l0, needle_shape * needle_shape * (e0 * e0)) * (e1 * e1))) return true;
    // The filter: a normal turning by less than about 89.9° (cos > 1e-3) is kept; otherwise the
    // exact orientation of the moved triangle in the plane of the old one decides. Judged
    // against the previous iteration and against the positions at the call: small turns add
    // up over iterations, and the promise is that no face is reversed with respect to the input.
    const Triangle_points after{Point_3(na.x, na.y, na.z), Point_3(nb.x, nb.y, nb.z), Point_3(nc.x, nc.y, nc.z)};
    const double d0 = dot(n0, n1);
    if (!(d0 > 0 && d0 * d0 > 1e-6 * l0 * l1)) {
      const Triangle_points before{Point_3(a.x, a.y, a.z), Point_3(b.x, b.y, b.z), Point_3(c.x, c.y, c.z)};
      if (orientation_flip_test(before, after) != Flip_state::kept) return true;
    }
    const V3 ni = load(initial_normal.data(), f);
    const double di = dot(ni, n1);
    const double li = dot(ni, ni);
    if (li > 0 && !(di > 0 && di * di > 1e-6 * li * l1)) {
      const V3 ia = load(oriented.data(), tri[0]), ib = load(oriented.data(), tri[1]), ic = load(oriented.data(), tri[2]);
      const Triangle_points initial{Point_3(ia.x, ia.y, ia.z), Point_3(ib.x, ib.y, ib.z), Point_3(ic.x, ic.y, ic.z)};
      if (orientation_flip_test(initial, after) != Flip_state::kept) return true;
    }
    // Nor may it fold over a neighbour: two faces sharing an edge that turn more than 90 degrees
    // apart, when they did not at the call (each face alone can turn less than 90 degrees and
    // the pair still fold; seen on CGAL's elephant). Filtered, then exact in the face's plane,
    // the test fit_template_to_curves verifies with. Across curve edges too: the faces on the two
    // sides of a curve move independently.
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t g = t.face_nbr[f][std::size_t(k)];
      if (g == no_face) continue;
      const V3 ng = load(next_normal.data(), g);
      const double dg = dot(n1, ng);
      if (dg > 0 && dg * dg > 1e-6 * l1 * dot(ng, ng)) continue;
      const auto& gt = m.triangles[g];
      const V3 ga = load(next.data(), gt[0]), gb = load(next.data(), gt[1]), gc = load(next.data(), gt[2]);
      const Triangle_points other{Point_3(ga.x, ga.y, ga.z), Point_3(gb.x, gb.y, gb.z), Point_3(gc.x, gc.y, gc.z)};
      if (orientation_in_plane(after, other[0], other[1], other[2]) == CGAL::POSITIVE) continue;
      const V3 ia = load(oriented.data(), tri[0]), ib = load(oriented.data(), tri[1]), ic = load(oriented.data(), tri[2]);
      const V3 ja = load(oriented.data(), gt[0]), jb = load(oriented.data(), gt[1]), jc = load(oriented.data(), gt[2]);
      const Triangle_points initial{Point_3(ia.x, ia.y, ia.z), Point_3(ib.x, ib.y, ib.z), Point_3(ic.x, ic.y, ic.z)};
      if (orientation_in_plane(initial, Point_3(ja.x, ja.y, ja.z), Point_3(jb.x, jb.y, jb.z),
                               Point_3(jc.x, jc.y, jc.z)) == CGAL::POSITIVE)
        return true;  // a new fold
    }
    return false;
  }

  // The iteration's figures, and `next` becomes the current positions.
  void finish_iteration(std::size_t it, std::size_t clamped_cot) {
    double step_max = 0;
    std::size_t clamped_walks = 0;
    bool all_finite = true;
#pragma omp parallel for schedule(static) if (parallel) reduction(max : step_max) reduction(+ : clamped_walks) reduction(&& : all_finite)
    for (std::ptrdiff_t si = 0; si < sn; ++si) {
      const std::size_t i = std::size_t(si);
      const V3 q = load(next.data(), i), d = q - load(P, i);
      all_finite = all_finite && finite(q);
      step_max = std::max(step_max, dot(d, d));
      if (!m.fixed[i] && modified && scale[i] > 0) clamped_walks += walk_clamped[i];
      // The modified Laplacian's reference does not change: the next walk starts where this
      // one landed. The modified mean curvature's reference is this iteration's mesh, on which
      // the vertex is a corner of its own faces.
      if (s.kind == Flow_kind::modified_laplacian && scale[i] > 0) home[i] = landing[i];
    }
    if (!all_finite) throw Numerical_error("smooth: a vertex position became non-finite in iteration " + std::to_string(it));
    cur.swap(next);
    report.clamped_cotangents += clamped_cot;
    report.projections_clamped += clamped_walks;
    report.last_step_max_displacement = std::sqrt(step_max);
    ++report.iterations;
  }

  Smoothing_arrays& m;
  const Flow_settings& s;
  Smoothing_report& report;
  const Topology& t;
  Flow_buffers& buffers;
  const std::size_t n, nf;
  const std::ptrdiff_t sn, snf;
  const bool modified, curvature;
  // The original positions p^0 (eq. 4.6) and the modified Laplacian's reference surface.
  std::vector<double> p0;
  const std::vector<double>& reference;
  const std::vector<double>& oriented;
  const double mean_edge;  // at the start of the run
  // The mean-curvature time step: λ h̄², so that λ is dimensionless (smooth.h).
  const double tau;
  const double min_distance;
  // Threads only pay off on large meshes: a step costs tens of nanoseconds per vertex, and on a
  // busy machine every barrier of a small mesh's step can cost a scheduler time slice.
  const bool parallel;
  std::vector<double> initial_normal;  // the normals of the faces at the call, for the flip guard
  std::vector<std::uint32_t> home;     // each vertex's face of the reference surface
  std::vector<double> cur, next, disp, scale, face_area2, edge_w;
  std::vector<double> next_normal, next_edge2;  // shape_at_next, by face
  std::optional<Reference_planes> ref_planes;  // the modified Laplacian's reference, whose planes do not change
  std::vector<std::array<double, 3>> face_cot;
  std::vector<std::uint32_t> landing;
  std::vector<unsigned char> walk_clamped, flipped;
  // Round stamps of the flip guard (which vertices and faces a round has already visited);
  // rounds are numbered from 1 in every iteration, so the stamps are reset per iteration.
  std::vector<std::uint32_t> vertex_round, face_round;
  std::vector<int> halvings;
  const double* P = nullptr;    // the current positions
  const double* ref = nullptr;  // what the modified flows project onto
};

// A mesh made by inserting vertices and splitting faces (stage 1's), or by midpoint subdivision,
// lists them in the order they were made, not where they are: a vertex's neighbours lie far apart
// in memory, and every step of a flow waits on the cache (`meshfit smooth`, 50 iterations, on the
// 1.3M-face scale case's output: 4.9-6.4 s as numbered, 2.5-2.8 s renumbered). When more than a quarter
// of the edges join vertices numbered more than far_apart apart (that output: 52 %), the flows
// run on a copy whose vertices are numbered in breadth-first order along the edges, from the
// lowest-numbered vertex of each component, and whose faces are sorted by their first vertex in
// that order; otherwise the copy would only cost its making (on a mesh of 1e5 vertices numbered
// by place, a tenth of a second). Both decisions read the connectivity alone: they do not depend
// on where the mesh is placed.
constexpr std::uint32_t far_apart = 8192;  // vertices: 192 KB of positions

bool numbered_far_apart(const Smoothing_arrays& m) {
  std::size_t far = 0;
  for (const auto& t : m.triangles)
    for (std::size_t j = 0; j < 3; ++j) {
      const std::uint32_t a = t[j], b = t[(j + 1) % 3];
      far += (a > b ? a - b : b - a) > far_apart;
    }
  return 4 * far > 3 * m.triangles.size();
}

// The vertices in breadth-first order:
std::vector<std::uint32_t> breadth_first_order(const Smoothing_arrays& m) {
  const std::size_t n = m.fixed.size();
  const Outgoing_half_edges out(m, n);
  std::vector<std::uint32_t> order;
  order.reserve(n);
  std::vector<unsigned char> seen(n, 0);
  for (std::uint32_t root = 0; root < n; ++root) {
    if (seen[root]) continue;
    seen[root] = 1;
    order.push_back(root);
    for (std::size_t head = order.size() - 1; head < order.size(); ++head) {
      const std::uint32_t v = order[head];
      for (std::uint32_t j = out.start[v]; j < out.start[v + 1]; ++j)
        if (!seen[out.target[j]]) seen[out.target[j]] = 1, order.push_back(out.target[j]);
    }
  }
  return order;
}

// m with vertex order[i] as vertex i, the faces sorted (stably) by their lowest new corner.
Smoothing_arrays renumbered(const Smoothing_arrays& m, const std::vector<std::uint32_t>& order) {
  const std::size_t n = order.size(), nf = m.triangles.size();
  std::vector<std::uint32_t> new_of(n);
  for (std::size_t i = 0; i < n; ++i) new_of[order[i]] = std::uint32_t(i);
  auto by_vertex = [&](const std::vector<double>& a) {
    std::vector<double> r(a.empty() ? 0 : 3 * n);
    if (!a.empty())
      for (std::size_t i = 0; i < n; ++i) store(r.data(), i, load(a.data(), order[i]));
    return r;
  };
  Smoothing_arrays r;
  r.points = by_vertex(m.points);
  r.reference_points = by_vertex(m.reference_points);
  r.orientation_points = m.orientation_points.size() == m.points.size() ? by_vertex(m.orientation_points) : m.orientation_points;
  r.fixed.resize(n);
  for (std::size_t i = 0; i < n; ++i) r.fixed[i] = m.fixed[order[i]];
  r.constrained_edges = m.constrained_edges;
  for (auto& e : r.constrained_edges)
    for (std::uint32_t& v : e) v = v < n ? new_of[v] : v;
  // Counting sort of the faces by their lowest corner.
  std::vector<std::uint32_t> start(n + 1, 0);
  auto lowest = [&](const std::array<std::uint32_t, 3>& t) { return std::min({new_of[t[0]], new_of[t[1]], new_of[t[2]]}); };
  for (const auto& t : m.triangles) ++start[lowest(t) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  r.triangles.resize(nf);
  for (const auto& t : m.triangles) r.triangles[start[lowest(t)]++] = {new_of[t[0]], new_of[t[1]], new_of[t[2]]};
  return r;
}

// run_flows on points of order one (see run_flows below), on a renumbered copy when the
// numbering is far apart.
void run_flows_unit(Smoothing_arrays& m, const std::vector<Flow_settings>& flows, Smoothing_report& report) {
  Fp_trap_scope traps;
  check_smoothing_input(m);
  auto run = [&](Smoothing_arrays& a) {
    const Topology t(a);
    Flow_buffers buffers;
    for (const Flow_settings& s : flows) Flow_run(a, s, report, t, buffers).run();
  };
  if (!numbered_far_apart(m)) return run(m);
  const std::vector<std::uint32_t> order = breadth_first_order(m);
  Smoothing_arrays r = renumbered(m, order);
  run(r);
  for (std::size_t i = 0; i < order.size(); ++i) store(m.points.data(), order[i], load(r.points.data(), i));
}

}  // namespace

// The flows run on the points scaled by a power of two to a unit-sized box (exact; unit_scale.h):
// the time step, the thresholds and the squared areas and cotangents then see numbers of order one
// at every supported scale (at 1e80, squared areas overflowed and angles came out wrong).
void run_flows(Smoothing_arrays& m, const std::vector<Flow_settings>& flows, Smoothing_report& report) {
  Bbox_3 box;  // of the vertices on a triangle (an unused vertex far away sets no scale)
  for (const auto& tri : m.triangles)
    for (const std::uint32_t i : tri)
      if (3 * std::size_t(i) + 2 < m.points.size()) {
        const double* p = &m.points[3 * std::size_t(i)];
        box += Bbox_3(p[0], p[1], p[2], p[0], p[1], p[2]);
      }
  const double unit = unit_scale(box);
  if (unit == 1) return run_flows_unit(m, flows, report);
  auto scale_all = [&](double f) {
    for (std::vector<double>* v : {&m.points, &m.reference_points, &m.orientation_points})
      for (double& x : *v) x *= f;
  };
  scale_all(unit);
  try {
    run_flows_unit(m, flows, report);
  } catch (...) {
    scale_all(1 / unit);
    throw;
  }
  scale_all(1 / unit);
  report.last_step_max_displacement /= unit;
}

void run_flow(Smoothing_arrays& m, const Flow_settings& s, Smoothing_report& report) { run_flows(m, {s}, report); }

}  // namespace internal
}  // namespace meshfit
