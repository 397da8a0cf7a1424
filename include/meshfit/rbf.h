// meshfit: radial basis function interpolation in 3D (thesis §2.2.2, eq. 2.6–2.10).
//
//   E(x) = Σ_j α_j φ(‖x − c_j‖) + R x + t,   Σ_j α_j = 0,  Σ_j α_j c_jᵀ = 0   (eq. 2.7)
//
// The centres are shifted to their centroid and scaled by their bounding-box diagonal before the
// system is built (values likewise), so a fit is unchanged by translating or scaling the input.
// The (n+4)×(n+4) system (eq. 2.8) is solved by LU with partial pivoting (Eigen).
#ifndef MESHFIT_RBF_H
#define MESHFIT_RBF_H

#include <meshfit/exceptions.h>
#include <meshfit/kernel.h>

#include <cstddef>
#include <string>
#include <vector>

namespace meshfit {

/// The basis function φ. Both are polyharmonic splines for which a linear polynomial term makes
/// the system uniquely solvable for centres spanning 3D.
enum class Rbf_kernel {
  linear,  ///< φ(r) = r, biharmonic in 3D: the thesis's choice, piecewise-linear-like interpolation
  cubic    ///< φ(r) = r³, triharmonic: smoother, may overshoot between centres (thesis fig. 2.5)
};
/// "linear" or "cubic" (the command line's spelling).
const char* to_string(Rbf_kernel kernel);

/// The largest relative residual ‖K X − Y‖ / ‖Y‖ accepted after the LU solve.
constexpr double rbf_residual_bound = 1e-9;
/// Systems whose estimated reciprocal condition number (1-norm) is below this are refused as
/// singular (Numerical_error) before they are solved.
constexpr double rbf_rcond_bound = 1e-15;
/// Centres whose affine block has a relative smallest singular value below this are treated as
/// coplanar (auxiliary pairs are added, see Rbf_interpolant::fit).
/// (Centres that thin leave the affine term along their normal, even its sign, to small offsets
/// of a few points: an open template nearly flat where the pairs are, say.)
constexpr double rbf_coplanarity_bound = 1e-2;

/// What a fit did.
struct Rbf_fit_report {
  std::size_t centres = 0;             ///< distinct centres used (after dropping exact repeats)
  std::size_t repeated_pairs = 0;      ///< pairs identical to an earlier one, dropped
  std::size_t auxiliary_pairs = 0;     ///< added: the centres were (nearly) coplanar, or (orientation_from_layout) mirrored
  double relative_residual = 0;        ///< of the linear solve
};

/// The interpolant E of eq. 2.7 through a set of pairs (centre → value), built by fit().
class Rbf_interpolant {
 public:
  /// An empty interpolant (no centres); use fit().
  Rbf_interpolant() = default;

  /// Fits E with E(centres[i]) = values[i].
  ///
  /// Coplanar centres (exact test, or nearly: see rbf_coplanarity_bound) do not determine the
  /// affine term along the plane's normal. As the thesis prescribes, auxiliary pairs are then
  /// added: each centre offset by a fifth of the centres' radius along the plane's normal (turned
  /// to the side of `normals`, the template's vertex normals, when given) maps to its value offset
  /// by a fifth of the values' radius along the values' thinnest direction, with the sign that
  /// keeps the orientation of the best affine map of the plane onto the values. The same pairs are
  /// added when `orientation_from_layout` is set (pairs on an open template, `normals` its
  /// facing) and the plain fit would mirror: the pairs' offsets across a patch are its shape, and
  /// their correlation says nothing about orientation.
  ///
  /// \throws Invalid_input (naming the pairs by 0-based index) for: sizes that differ, a
  ///         non-finite coordinate, fewer than 4 distinct centres, two equal centres with
  ///         different values, all centres collinear (or equal).
  /// \throws Numerical_error when the system is singular (rbf_rcond_bound), or the solve yields
  ///         a non-finite value or a relative residual above rbf_residual_bound.
  /// \throws Algorithm_failure ("deform") before any allocation when the dense system and its
  ///         factorisation (2·8·(n+4)² bytes for n centres) would exceed `memory_limit` bytes
  ///         (0: default_memory_limit(), see memory_limit.h).
  static Rbf_interpolant fit(const std::vector<Point_3>& centres, const std::vector<Point_3>& values,
                             Rbf_kernel kernel = Rbf_kernel::linear,
                             const std::vector<Vector_3>& normals = {},
                             Rbf_fit_report* report = nullptr, std::size_t memory_limit = 0,
                             bool orientation_from_layout = false);

  /// E(p).
  Point_3 operator()(const Point_3& p) const;

  /// out[i] = E(in[i]) for all i: O(in.size() × centres) work, blocked and vectorised, on
  /// `threads` threads (0: all cores), memory O(in.size() + centres). `out` may alias `in`.
  void evaluate(const std::vector<Point_3>& in, std::vector<Point_3>& out, unsigned threads = 0) const;

  /// The affine term R x + t of E alone (eq. 2.7), at p.
  Point_3 affine_part(const Point_3& p) const;
  /// det R: negative when the affine term mirrors space, so that the interpolant maps the
  /// template onto a mirror image of itself (the pairs reverse the orientation). Unchanged by a
  /// rotation, translation or uniform scaling of the centres or of the values.
  double affine_determinant() const;

  /// The number of centres, auxiliary pairs included.
  std::size_t number_of_centres() const { return m_cx.size(); }
  /// The basis function φ of the fit.
  Rbf_kernel kernel() const { return m_kernel; }

 private:
  // The interpolation system through exactly these pairs; sets the solve's relative residual.
  static Rbf_interpolant solve(const std::vector<Point_3>& centres, const std::vector<Point_3>& values,
                               Rbf_kernel kernel, std::size_t memory_limit, double& residual);

  Rbf_kernel m_kernel = Rbf_kernel::linear;
  // Normalisation: x̂ = (x − m_shift_in) · m_scale_in; E(x) = m_shift_out + Ê(x̂) / m_scale_out.
  Vector_3 m_shift_in{0, 0, 0}, m_shift_out{0, 0, 0};
  double m_scale_in = 1, m_scale_out = 1;
  // Normalised centres and weights, structure of arrays for the vectorised evaluation.
  std::vector<double> m_cx, m_cy, m_cz, m_ax, m_ay, m_az;
  double m_affine[4][3] = {};  // rows: x, y, z, 1
};

}  // namespace meshfit

#endif  // MESHFIT_RBF_H
