// geometry/: the spaces curves live in, one header per geometry holding everything that
// geometry provides (points, tangents, exp/log, geodesic steps, twist conversion, jet →
// kinematics, finiteness and tolerance scales, the sphere's three-point circle):
//   geodesic.h             geodesic interpolation, the operation every construction uses
//   tangent_space.h        velocity (T1) and acceleration (T2) of a curve in G's tangent
//                          representation; orthonormal tangent coordinates for the solvers
//   pose.h                 SE(3) points shared by both SE(3) geometries: Twist, Kinematics,
//                          the twist ↔ tangent conversions' interface
//   screw_se3.h            ScrewSe3: SE(3) with its screw (Ad-invariant) metric
//   double_geodesic_se3.h  DoubleGeodesicSe3: SO(3) × R³, slerp + lerp
//   so3.h                  So3: rotations alone
//   euclidean.h            Euclidean: R^n, the abelian reference
//   sphere.h               Sphere: S^m ⊂ R^{m+1} (Crouch, Kun, Silva Leite)
// This header includes them all.
//
// The policy interface. The geometries a curve can live in are policies for the generic algorithms.
//
// Every geometry G provides
//   template <class S> using Point;     // a point of the manifold, scalar S
//   template <class S> using Tangent;   // a tangent vector (representation below)
//   log(a, b) -> Tangent                // the initial velocity of the geodesic a → b at λ = 0
//   exp(a, v) -> Point                  // the geodesic from a with initial velocity v, at λ = 1
//   cast<T>(Point<double>) -> Point<T>
// so that the geodesic interpolation of thesis eq. (4.1) is
//   interp_λ(a, b) = exp(a, λ log(a, b)),
// defined for every real λ (λ outside [0, 1] extrapolates along the geodesic).
// log throws NonUniqueGeodesicError when a and b are antipodal (the minimising
// geodesic is not unique).
//
// Tangent representations:
//   ScrewSe3:          body twist (ω, v) of a⁻¹b, rotation first (se(3), thesis ch. 5)
//   DoubleGeodesicSe3: (ω, Δp): ω the body rotation vector of R_aᵀ R_b, Δp = p_b − p_a in
//                      the world frame (product metric SO(3) × R³)
//   So3:               body rotation vector ω of q_a⁻¹ q_b
//   Euclidean:         b − a in R^n
//   Sphere:            the ambient vector in T_a S^m ⊂ R^{m+1} (Crouch et al., eq. 17/18)
#pragma once

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/geometry/tangent_space.h"
#include "se3_interpolation/geometry/pose.h"
#include "se3_interpolation/geometry/screw_se3.h"
#include "se3_interpolation/geometry/double_geodesic_se3.h"
#include "se3_interpolation/geometry/so3.h"
#include "se3_interpolation/geometry/euclidean.h"
#include "se3_interpolation/geometry/sphere.h"
