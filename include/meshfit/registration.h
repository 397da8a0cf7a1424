// meshfit: a global registration of the template to the curves, by a quadratic warp of space
// fitted with Coherent Point Drift (Myronenko and Song 2010, "Point set registration: coherent
// point drift", IEEE TPAMI 32(12)), the user's pairs held as weighted constraints.
//
// The warp is W(x) = x + Cᵀ b(u), u = (x − c) / s, where b(u) holds the ten monomials of degree
// at most 2 of u (c the centroid of the template's points, s their RMS distance from it): an
// affine map plus a quadratic bend, a space of maps unchanged by a rigid motion or a uniform
// scaling of the template. Each network point is a sample of a Gaussian mixture centred on the
// warped template points (with a uniform term for outliers); EM alternates the posteriors with a
// weighted least-squares solve for C, the variance shrinking as the fit improves, so that early
// iterations see the whole shape (every curve pulls on every part within reach) and later ones
// the nearest parts. Unlike closest-point matching, a loop of the network that lies nearer the
// wrong limb after the RBF through a few pairs is carried with the rest of the network.
//
// It is the coarse level's second start (deform_template): when the fine level leaves defects
// after the RBF through the pairs alone, the template is warped first and the level runs again.
#ifndef MESHFIT_REGISTRATION_H
#define MESHFIT_REGISTRATION_H

#include <meshfit/kernel.h>

#include <array>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace meshfit {

/// x ↦ x + Cᵀ b((x − centre) / scale), b the monomials 1, u₀, u₁, u₂, u₀², u₀u₁, u₀u₂, u₁², u₁u₂, u₂².
struct Quadratic_warp {
  Point_3 centre = Point_3(0, 0, 0);  ///< c, the origin of u
  double scale = 1;                    ///< s, the unit of u
  std::array<std::array<double, 3>, 10> coefficients{};  ///< C, by monomial (all zero: the identity)

  /// W(p).
  Point_3 operator()(const Point_3& p) const;
  /// det ∂W/∂x at p.
  double jacobian_determinant(const Point_3& p) const;
};

/// What register_quadratic_warp did.
struct Registration_report {
  std::size_t iterations = 0;      ///< EM iterations
  double final_sigma = 0;          ///< the mixture's standard deviation at the end, over the network points' RMS radius
  /// Mean distance of the network points taking part to the nearest template point taking part,
  /// over the network points' RMS radius: after the affine map through the pairs (the start) ...
  double mean_distance_before = 0;
  double mean_distance_after = 0;  ///< ... and after the warp
  /// The warp found turns space over at a template point (det ∂W/∂x ≤ 0) and was not returned.
  bool turns_over = false;
};

/// The quadratic warp that brings `template_points` (the template's vertices on faces) onto
/// `network_points` by Coherent Point Drift, with W(pairs[k].first) = pairs[k].second asked with
/// the weight of all network points together. At most 3000 points of each set take part (every
/// k-th, in the given order). Starts from the affine map through the pairs (least squares).
/// Returns nothing when the warp turns space over at one of `template_points` (det ∂W/∂x ≤ 0: a
/// face there would turn over) or when the sets are too small to fit it (fewer than 4 points,
/// or no pair).
std::optional<Quadratic_warp> register_quadratic_warp(const std::vector<Point_3>& template_points,
                                                      const std::vector<Point_3>& network_points,
                                                      const std::vector<std::pair<Point_3, Point_3>>& pairs,
                                                      Registration_report* report = nullptr);

}  // namespace meshfit

#endif  // MESHFIT_REGISTRATION_H
