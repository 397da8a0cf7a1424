// meshfit: a global registration of the template to the curves, by a quadratic warp of space
// fitted with Coherent Point Drift (Myronenko and Song 2010, "Point set registration: coherent
// point drift", IEEE TPAMI 32(12)) and with point-to-plane closest-point fits, the user's pairs
// held as weighted constraints.
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
// Closest-point fits (point-to-plane ICP) of the same warp are made beside it when the template's
// triangles are given, and the warp whose surface lies nearest the network points is returned:
// on the battery's six real-* cases the two kinds of fit each win on some (bench/battery).
//
// It is the coarse level's second start (deform_template): when the fine level leaves defects
// after the RBF through the pairs alone, the template is warped first and the level runs again
// (and a third time from the drift's warp, when the warp used was another and defects remain).
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

/// Which fit gave the warp register_quadratic_warp returned.
enum class Registration_method { coherent_point_drift, closest_point };

/// What register_quadratic_warp did.
struct Registration_report {
  std::size_t iterations = 0;      ///< EM iterations of the Coherent Point Drift
  double final_sigma = 0;          ///< the mixture's standard deviation at the end, over the network points' RMS radius
  std::size_t closest_point_iterations = 0;  ///< iterations of the closest-point fits, all together
  std::size_t candidates = 0;      ///< warps fitted: the drift, and the 4 closest-point fits when there are triangles
  std::size_t candidates_turning_over = 0;  ///< of which turn space over at a template point (left out)
  /// of the others, those that bring every pair within its tolerance (all of them when no
  /// tolerances are given)
  std::size_t candidates_keeping_pairs = 0;
  /// Mean distance of the network points taking part to the warped template (its triangles; its
  /// nearest point when no triangles are given), over the network points' RMS radius: after the
  /// affine map through the pairs (the start) ...
  double mean_distance_before = 0;
  double mean_distance_after = 0;  ///< ... and after the warp returned
  Registration_method method = Registration_method::coherent_point_drift;  ///< the fit returned
  double pair_weight = 1;          ///< the pairs' weight, relative to all matches together, in that fit
  bool far_matches_left_out = false;  ///< that fit left out matches beyond three times the median distance
  /// Every warp found turns space over at a template point (det ∂W/∂x ≤ 0): none was returned.
  bool turns_over = false;
};

/// The quadratic warp that brings `template_points` (the template's vertices on faces) onto
/// `network_points`. Coherent Point Drift asks W(pairs[k].first) = pairs[k].second with the weight
/// of all network points together; at most 3000 points of each set take part (every k-th, in the
/// given order). With `triangles` (corner indices into `template_points`), four closest-point fits
/// are made as well when at least 4 points lie on a triangle (at most 20000 of them, normals from
/// the triangles, each network point matched with the nearest; pairs weighing 1,
/// 1 with far matches left out, 0.1 and 0.01 times all matches), and of the warps that do not
/// turn space over at any of `template_points` (det ∂W/∂x ≤ 0: a face there would turn over), the
/// one whose warped triangles lie nearest the network points (mean distance) is returned,
/// preferring those that bring every pair's template point within `pair_tolerances[k]` (in the
/// template's units, times the warp's local change of length ∛det ∂W/∂x) of its network point:
/// a user's pair names a template vertex near the curve point, not its exact preimage, and a fit
/// that weighs the pairs little can slide the template along the curves (empty: no tolerance). Every
/// fit starts from the affine map through the pairs (least squares). Returns nothing when every
/// warp turns space over, or when the sets are too small to fit one (fewer than 4 points, or no
/// pair).
/// `drift_warp`, when given, receives the Coherent Point Drift's warp (nothing when it turns space
/// over), which a caller may try next when the warp returned does not serve.
/// \throws Invalid_input when a triangle's corner is out of range, or `pair_tolerances` is neither
///         empty nor one per pair.
std::optional<Quadratic_warp> register_quadratic_warp(const std::vector<Point_3>& template_points,
                                                      const std::vector<std::array<std::size_t, 3>>& triangles,
                                                      const std::vector<Point_3>& network_points,
                                                      const std::vector<std::pair<Point_3, Point_3>>& pairs,
                                                      const std::vector<double>& pair_tolerances = {},
                                                      Registration_report* report = nullptr,
                                                      std::optional<Quadratic_warp>* drift_warp = nullptr);

}  // namespace meshfit

#endif  // MESHFIT_REGISTRATION_H
