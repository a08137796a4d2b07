// SE(3) points, shared by both SE(3) geometries (screw_se3.h, double_geodesic_se3.h): the
// spatial twist of requests and responses, the kinematics of a pose curve from its jet, and
// the conversions between twists and each geometry's tangent representation.
//
// Frames and units. A pose is world_T_body = (R, p): R rotates body coordinates into the
// waypoints' frame, p (m) is the body origin in that frame. Requests (README, "Conventions
// (frames and units)") give a velocity as the spatial twist (ṗ, ω) with Ṙ = [ω]× R (m/s,
// rad/s), and an acceleration as (p̈, ω̇) (m/s², rad/s²), all in the waypoints' frame.
//
// Kinematics from the second-order jet of a pose (q(t), p(t)) at t:
//   linear velocity  ṗ,            linear acceleration  p̈,
//   angular velocity ω = 2 vec(q̇ q*)  (so that Ṙ = [ω]× R: spatial, the waypoints' frame),
//   angular accel.   ω̇ = 2 vec(q̈ q*)  (vec(q̇ q̇*) = 0 for a unit quaternion).
//
// Twist conversions. The curve constructions work with tangents in G's representation at the
// point x = (R, p) where the motion happens, velocity (T1) and acceleration (T2) as defined in
// tangent_space.h; each geometry specialises Se3TangentConversion<G> with its formulas ((V1),
// (A1) in screw_se3.h, (V2), (A2) in double_geodesic_se3.h).
#pragma once

#include <Eigen/Core>

#include "se3_interpolation/geometry/geodesic.h"
#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
/// A spatial twist or its time derivative: linear (m/s or m/s²) and angular (rad/s or rad/s²)
/// parts, both in the waypoints' frame (Ṙ = [ω]× R).
struct Twist
{
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

/// Pose, velocity and acceleration of a pose curve at one instant (spatial twists).
struct Kinematics
{
  Pose<double> pose;
  Twist velocity;
  Twist acceleration;
};

/// Velocity and acceleration of a pose curve at one instant without its pose: the parts of Twist,
/// each in the frame that the function returning them names.
struct MotionRates
{
  Twist velocity;
  Twist acceleration;
};

/// MotionRates with the jerk (p⃛ and ω̈, in the frames the producer names).
struct MotionRates3
{
  Twist velocity;
  Twist acceleration;
  Twist jerk;
};

/// The kinematics from the second-order jet of a pose (file comment): ṗ, p̈, ω = 2 vec(q̇ q*), ω̇ = 2 vec(q̈ q*)
/// (the jet holds q̈/2 as its second coefficient, hence the factor 4).
inline Kinematics kinematicsFromJet(const Pose<Jet<2>>& x)
{
  Kinematics k;
  const Quaternion<double> q0(x.q.w().value(), x.q.x().value(), x.q.y().value(), x.q.z().value());
  const Quaternion<double> q1(x.q.w().coefficient(1), x.q.x().coefficient(1), x.q.y().coefficient(1),
                              x.q.z().coefficient(1));
  const Quaternion<double> q2(x.q.w().coefficient(2), x.q.x().coefficient(2), x.q.y().coefficient(2),
                              x.q.z().coefficient(2));
  k.pose.q = q0;
  for (int i = 0; i < 3; ++i)
  {
    k.pose.p[i] = x.p[i].value();
    k.velocity.linear[i] = x.p[i].coefficient(1);
    k.acceleration.linear[i] = 2.0 * x.p[i].coefficient(2);
  }
  const Quaternion<double> q0c = q0.conjugate();
  k.velocity.angular = 2.0 * (q1 * q0c).vec();
  k.acceleration.angular = 4.0 * (q2 * q0c).vec();
  return k;
}

/// The types both SE(3) geometries share: points are poses, tangents 6-vectors (rotation first).
using PoseGeometryTypes = CoordinateTypes<Pose, Vector6>;

/// Whether every coordinate of a pose is finite.
inline bool allFinite(const Pose<double>& x)
{
  return x.p.allFinite() && x.q.coeffs().allFinite();
}

/// A scale for absolute tolerances on poses: 1 + |p| (m).
inline double pointMagnitude(const Pose<double>& x)
{
  return 1.0 + x.p.norm();
}

/// The conversions for one SE(3) geometry (specialised below).
template <class G>
struct Se3TangentConversion;

/// G's velocity tangent (T1) at x of the motion with spatial twist `velocity`.
template <class G>
Vector6<double> velocityToTangent(const Pose<double>& x, const Twist& velocity)
{
  return Se3TangentConversion<G>::velocity(x, velocity);
}

/// The spatial twist (ṗ, ω) of the motion with velocity tangent `tangent` at x.
template <class G>
Twist tangentToVelocity(const Pose<double>& x, const Vector6<double>& tangent)
{
  return Se3TangentConversion<G>::twist(x, tangent);
}

/// G's acceleration tangent (T2) at x of the motion with spatial velocity and acceleration.
template <class G>
Vector6<double> accelerationToTangent(const Pose<double>& x, const Twist& velocity, const Twist& acceleration)
{
  return Se3TangentConversion<G>::acceleration(x, velocity, acceleration);
}

/// The spatial acceleration (p̈, ω̇) of the motion with spatial velocity `velocity` and
/// acceleration tangent `tangent` (T2) at x.
template <class G>
Twist tangentToAcceleration(const Pose<double>& x, const Twist& velocity, const Vector6<double>& tangent)
{
  return Se3TangentConversion<G>::twistAcceleration(x, velocity, tangent);
}

}  // namespace se3_interpolation
