// meshfit: smooth displacement fields on a mesh with some vertices' displacements given (the
// linear variational deformation of Botsch & Sorkine 2008, "On linear variational surface
// deformation methods", §3: the displacement d minimises the membrane energy ∫‖∇d‖² (order 1,
// Δd = 0 on the free vertices) or the thin-plate energy ∫‖Δd‖² (order 2, Δ²d = 0), with the given
// vertices as hard constraints).
//
// The Laplacian is the uniform (graph) one, Δd_i = mean of d_j over the neighbours j of i, minus
// d_i: its weights are positive on every mesh, so the membrane solution is a convex combination
// of the given displacements at every free vertex (a discrete maximum principle) and cannot
// overshoot them. In the thin-plate energy a border vertex's Laplacian is taken along the border
// (over its border neighbours, when Vertex_adjacency::border_edge says which): the mean over all
// its neighbours, all on one side, measures the field's slope across the border, and asking it
// to vanish would hold a curved border flat. The sparse system on the free vertices is solved
// by CHOLMOD's supernodal Cholesky factorisation; its size grows like the mesh, not like the
// number of constraints.
#ifndef MESHFIT_DISPLACEMENT_H
#define MESHFIT_DISPLACEMENT_H

#include <meshfit/kernel.h>

#include <array>
#include <cstddef>
#include <vector>

namespace meshfit {

/// A mesh's vertex adjacency in compressed rows: the neighbours of vertex i are
/// `neighbours[offsets[i]] … neighbours[offsets[i + 1] - 1]`.
struct Vertex_adjacency {
  std::vector<std::size_t> offsets{0};  ///< one more than the number of vertices, offsets[0] = 0
  std::vector<std::size_t> neighbours;  ///< the neighbours of every vertex, row after row
  /// Optional, beside `neighbours` (empty: no edge is on a border): whether the edge to each
  /// neighbour lies on the mesh's border. The thin-plate energy takes a border vertex's
  /// Laplacian along the border, over its border neighbours alone (see interpolate_displacements).
  std::vector<bool> border_edge;
  /// Optional, beside `neighbours` (empty: every weight 1, the uniform Laplacian): the weight of
  /// the edge to each neighbour, the same from both ends (set_cotangent_weights).
  std::vector<double> weight;
  /// Optional, one per vertex (empty: each vertex's number of neighbours): the mass that divides
  /// a vertex's Laplacian in the thin-plate energy.
  std::vector<double> mass;
  /// The number of vertices.
  std::size_t size() const { return offsets.size() - 1; }
};

/// What a displacement solve did.
struct Displacement_report {
  std::size_t free_vertices = 0;         ///< vertices whose displacement was solved for
  std::size_t constrained_vertices = 0;  ///< vertices whose displacement was given
  std::size_t nonzeros = 0;  ///< of the factored matrix
  /// Free vertices in a connected part of the mesh with no constrained vertex: they keep a zero
  /// displacement.
  std::size_t unconstrained_free_vertices = 0;
  /// Set by deform_fine_on_surface: vertices it held in place beyond the band along the curves
  /// where it solved (counted apart from `constrained_vertices`).
  std::size_t held_beyond_band = 0;
};

/// The neighbours of each of `n` vertices by the edges of `triangles` (corner indices), each row
/// sorted and without repeats; no weights, masses or border flags (a vertex on no triangle has an
/// empty row).
/// \throws Invalid_input naming the first triangle with a corner out of range.
Vertex_adjacency triangle_adjacency(std::size_t n, const std::vector<std::array<std::size_t, 3>>& triangles);

/// Sets `adjacency.weight` and `adjacency.mass` to the cotangent Laplacian of the mesh at `points`
/// (`triangles`: its faces, corner indices into `points`), scaled so that a mesh of equilateral
/// triangles keeps weight 1 and mass equal to the number of neighbours (the uniform Laplacian's):
/// w_ij = (√3/2)(cot α + cot β) with each cotangent bounded by cot(10°) in magnitude and w_ij at
/// least 0.05 (an obtuse pair of angles would make it negative), mass_i = 6 A_i / Ā (A_i a third
/// of the area of i's faces, Ā their mean over the vertices on a face, A_i at least 0.001 Ā). The
/// thin-plate field on these weights approximates the surface's own bi-Laplacian where the
/// uniform one follows the mesh's vertex density: on a template whose triangles vary in size and
/// shape the uniform field bends towards the finer part. Dimensionless: the same for the mesh
/// moved, turned or scaled. The bound on the cotangents keeps a mesh with slivers (curves just
/// embedded) from weights that are huge on one edge: on bench/battery's ico10242-peanut-latlong
/// the thin-plate fill through the curves on cot(1°)-bounded weights ended 2.41 % of the diagonal
/// from the truth with 162 faces turned over, on cot(10°)-bounded ones 0.65 % with 23.
/// \throws Invalid_input when a triangle's corner is out of range or is not a neighbour of the
/// other two in `adjacency`.
void set_cotangent_weights(Vertex_adjacency& adjacency, const std::vector<Point_3>& points,
                           const std::vector<std::array<std::size_t, 3>>& triangles);

/// K x per vertex: the Laplacian of the points under `adjacency`'s rows (its weights; 1 when it
/// has none), Σ_j w_ij (x_i − x_j) over the vertex's row (along the border for a border row).
/// \throws Invalid_input when the sizes differ.
std::vector<Vector_3> laplacian_of(const Vertex_adjacency& adjacency, const std::vector<Point_3>& points);

/// How a surface bends at each of its vertices: the cotangent Laplacian (set_cotangent_weights)
/// of its points along the unit vertex normal, per unit of vertex area (A_i as there; about
/// 2√3·H, H the mean curvature, positive where the surface is convex towards its normals; 0
/// on a plane). With bent_laplacian it carries a template's shape onto a mesh of other vertices
/// and another metric: the "detail" of Laplacian editing, without the template's coordinates.
/// \throws Invalid_input on a corner out of range.
std::vector<double> normal_bending(const std::vector<Point_3>& points, const std::vector<std::array<std::size_t, 3>>& triangles);

/// The Laplacian (per vertex) that a mesh at `points` has when it bends by `bending` (per vertex,
/// normal_bending's measure): bending_i · A_i · n_i, with the area and unit normal of vertex i at
/// `points`.
/// \throws Invalid_input when the sizes differ.
std::vector<Vector_3> bent_laplacian(const std::vector<double>& bending, const std::vector<Point_3>& points,
                                     const std::vector<std::array<std::size_t, 3>>& triangles);

/// The displacement of every vertex: `given[i]` where `constrained[i]`, and the minimiser of the
/// membrane (order 1) or thin-plate (order 2) energy elsewhere (see the top of this file). With
/// `target_laplacian` t (order 2 only), the thin-plate energy is measured against it:
/// (K d − t)ᵀ M⁻¹ (K d − t), so that points x moved by d take the Laplacian K x + t (Laplacian
/// editing: t = δ − K x gives the moved points the Laplacian coordinates δ).
/// \throws Invalid_input when the sizes differ, `order` is not 1 or 2, or a given displacement is
///         not finite; Numerical_error when the factorisation fails.
std::vector<Vector_3> interpolate_displacements(const Vertex_adjacency& adjacency, const std::vector<bool>& constrained,
                                                const std::vector<Vector_3>& given, int order = 2,
                                                Displacement_report* report = nullptr,
                                                const std::vector<Vector_3>* target_laplacian = nullptr);

/// The vertices within reach of a constrained vertex, each constrained vertex i reaching the
/// larger of `rings` and ⌈`fade` ‖given[i]‖ / `edge`⌉ edges out (edges of `adjacency`; a
/// displacement too large to count, or not finite, reaches every vertex). A thin-plate field
/// through small motions, held at zero beyond them, fades from each motion to nothing over at
/// least `fade` times its length (deform_fine_on_surface, step 3).
/// \throws Invalid_input when the sizes differ or `edge` is not positive.
std::vector<bool> vertices_within_reach(const Vertex_adjacency& adjacency, const std::vector<bool>& constrained,
                                        const std::vector<Vector_3>& given, double edge, std::size_t rings,
                                        double fade);

/// A soft constraint of fit_displacements: the displacement at a point of a face (its corners'
/// displacements weighted by the point's barycentric coordinates) should be `target`.
struct Soft_displacement {
  std::array<std::size_t, 3> corners{};      ///< the face's corners (vertex indices)
  std::array<double, 3> barycentric{};      ///< the point's weights on them
  Vector_3 target{0, 0, 0};                 ///< the displacement asked for there
  double weight = 1;                        ///< the constraint's weight (not negative)
};

/// A coarse space for fit_displacements: displacements d = P c interpolated from a few nodes, so
/// that a large mesh's system is solved on the nodes (the Galerkin system Pᵀ A P) rather than on
/// every vertex. The nodes are aggregates of vertices (each grown `rings` edges out from a seed
/// vertex, at the seed's point); a vertex interpolates the nodes up to two aggregates away that
/// reach it, by moving least squares in its tangent plane (weights (1 − r²/R²)³, R a node's
/// distance to the farthest node beside it; widened for a vertex that fewer than three nodes
/// around it reach, at a border), which reproduces every displacement linear along the surface:
/// a smooth field is not held back by the coarse space (constants alone, as in smoothed
/// aggregation, lock the thin-plate energy: the fit of a 327 680-face template ended 4 times
/// farther from its target). P is stored by rows.
struct Coarse_space {
  std::size_t nodes = 0;                ///< the number of nodes (columns of P)
  std::vector<std::size_t> seed;        ///< each node's seed vertex (the node is at its point)
  std::vector<std::size_t> offsets{0};  ///< row i of P: entries offsets[i] … offsets[i + 1] - 1
  std::vector<std::size_t> node;        ///< each entry's node
  std::vector<double> weight;           ///< each entry's weight (a row sums to 1)
};

/// The coarse space of a mesh with the given adjacency, vertex points and normals (any length;
/// a zero or non-finite normal makes that vertex's weights those of the nearest-node average).
/// \throws Invalid_input when the sizes differ or `rings` is 0.
Coarse_space coarse_space(const Vertex_adjacency& adjacency, const std::vector<Point_3>& points,
                          const std::vector<Vector_3>& normals, std::size_t rings);

/// The displacement d minimising Σ weight·‖Σ_k barycentric_k d_{corner_k} − target‖² +
/// stiffness · (thin-plate energy of d, uniform Laplacian as above): the least-squares step of a
/// non-rigid ICP (the stiffer, the smoother). Parts of the mesh with no constraint keep a zero
/// displacement. With `coarse` (built for this adjacency), d is sought in its span: the minimiser
/// there (the whole mesh's solve when the coarse system cannot be factored).
/// \throws Invalid_input on a corner out of range, a non-finite target, a stiffness that is not
/// positive or a coarse space of another size or malformed (rows out of order, a node out of
/// range, a weight not finite); Numerical_error when the factorisation fails.
std::vector<Vector_3> fit_displacements(const Vertex_adjacency& adjacency, const std::vector<Soft_displacement>& constraints,
                                        double stiffness, const Coarse_space* coarse = nullptr);

}  // namespace meshfit

#endif  // MESHFIT_DISPLACEMENT_H
