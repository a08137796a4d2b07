// Velocities and accelerations of curves in a geometry's own tangent representation,
// and coordinates on the tangent spaces for the iterative solvers.
//
// Definition (used by every interpolating construction). For a curve c in geometry G
// (geometry.h) and a time t, look at the curve in the chart of G centred at x = c(t):
//   y(s) = G::log(x, c(t + s)) ∈ T_x,       y(0) = 0,
// and define
//   velocity      v = y'(0),                                                     (T1)
//   acceleration  a = y''(0).                                                    (T2)
// Since G::log(x, ·) inverts G::exp(x, ·) near x, v is the tangent with
// d/ds G::exp(x, s v)|_{s=0} = ċ(t), in G's representation (geometry.h). Along a geodesic
// of G, y(s) = s v exactly, so a = 0: this is "the acceleration that vanishes along the
// geodesics of G". In the geometries of this library (derivations in screw_se3.h, double_geodesic_se3.h):
//   ScrewSe3:           a = d/dt of the body twist (Rᵀω, Rᵀṗ) = (Rᵀω̇, Rᵀ(p̈ − ω × ṗ)),
//                       because the body twist is ξ = J_r(y) y' with J_r(y) = I − ½ ad_y + O(|y|²),
//                       so ξ'(0) = y''(0) − ½ [y'(0), y'(0)] = y''(0);
//   DoubleGeodesicSe3:  a = (Rᵀω̇, p̈) (the same on SO(3), the plain second derivative on R³);
//   So3:                a = Rᵀω̇;
//   Euclidean:          a = p̈;
//   Sphere:             y are Riemannian normal coordinates (the Christoffel symbols vanish at
//                       their centre), so a is the covariant acceleration c̈ − (c̈·c) c, the
//                       D²/dt² of Crouch–Kun–Silva Leite Thm 2.9 and Case 2.
// Because y is a chart, two curves through x agree to second order iff their (v, a) agree:
// matching (v, a) at a junction is C² continuity.
//
// Tangent coordinates. The representation of a tangent vector may be redundant (the sphere's
// ambient vectors in R^{m+1} span an m-dimensional tangent space). TangentFrame<G>::basis(x)
// returns a matrix B with orthonormal columns spanning T_x in the representation, so that
// tangent vectors are B z, z ∈ R^dof; for the groups and R^n it is the identity.
#pragma once

#include <Eigen/Core>

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/math/jet.h"

namespace se3_interpolation
{
/// The value (zeroth Taylor coefficient) of a point evaluated in jet arithmetic.
template <int K>
Pose<double> jetValue(const Pose<Jet<K>>& x)
{
  return Pose<double>(Quaternion<double>(x.q.w().value(), x.q.x().value(), x.q.y().value(), x.q.z().value()),
                      Eigen::Vector3d(x.p.x().value(), x.p.y().value(), x.p.z().value()));
}
template <int K>
Quaternion<double> jetValue(const Quaternion<Jet<K>>& q)
{
  return Quaternion<double>(q.w().value(), q.x().value(), q.y().value(), q.z().value());
}
template <int K>
Eigen::VectorXd jetValue(const VectorX<Jet<K>>& x)
{
  return x.unaryExpr([](const Jet<K>& c) { return c.value(); });
}

/// The k-th Taylor coefficients of a vector of jets.
template <int K, int R>
Eigen::Matrix<double, R, 1> jetCoefficients(const Eigen::Matrix<Jet<K>, R, 1>& v, int k)
{
  return v.unaryExpr([k](const Jet<K>& c) { return c.coefficient(k); });
}

/// Velocity (T1) and acceleration (T2) of a curve in G's tangent representation at its point.
template <class G>
struct TangentMotion
{
  typename G::template Tangent<double> velocity;
  typename G::template Tangent<double> acceleration;
};

/// (T1), (T2) from the second-order jet of a curve at one instant (centre: the jet's value).
template <class G>
TangentMotion<G> tangentMotion(const typename G::template Point<Jet<2>>& x)
{
  using Point2 = typename G::template Point<Jet<2>>;
  const Point2 centre = G::template cast<Jet<2>>(jetValue(x));
  const typename G::template Tangent<Jet<2>> y = G::log(centre, x);
  TangentMotion<G> m;
  m.velocity = jetCoefficients(y, 1);
  m.acceleration = 2.0 * jetCoefficients(y, 2);
  return m;
}

/// Size of G's tangent representation at x (6 on SE(3), 3 on SO(3), n on R^n, m + 1 on S^m).
template <class G>
Eigen::Index tangentDimension(const typename G::template Point<double>& x)
{
  return G::log(x, x).size();
}

/// Orthonormal coordinates on the tangent spaces: the default for geometries whose tangent
/// representation is a coordinate system (Lie groups, R^n); the sphere specialises it (sphere.h).
template <class G>
struct TangentFrame
{
  static constexpr bool kIdentity = true;
  static Eigen::MatrixXd basis(const typename G::template Point<double>& x)
  {
    const Eigen::Index n = tangentDimension<G>(x);
    return Eigen::MatrixXd::Identity(n, n);
  }
};

}  // namespace se3_interpolation
