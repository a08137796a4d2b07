// Truncated Taylor arithmetic ("jets") for exact time derivatives of curves.
//
// A Jet<K> holds the Taylor coefficients c_0 … c_K of a scalar function of time
// around one instant: f(t0 + h) = Σ c_k h^k + O(h^{K+1}), so f^{(k)}(t0) = k! c_k.
// Every curve in this library is written once over a scalar type S; evaluating
// it at the jet (t0, 1, 0, …) propagates exact derivatives through the closed-form
// exp/log maps and the de Casteljau / de Boor recursions (forward-mode
// differentiation: analytic, not finite differences; rounding errors only).
//
// The elementary functions use the classical Taylor recurrences (Griewank &
// Walther, "Evaluating Derivatives", ch. 13). Comparisons act on the value c_0,
// so branches (small-angle series, sign flips) select the same closed form a
// plain double would.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>

// The coefficient loops have compile-time bounds; unrolling and inlining them matters
// (a Jet<2> product is 6 multiply-adds, not a call into a generic loop).
#define SE3_JET_PRAGMA(x) _Pragma(#x)
#if defined(__clang__)
// clang unrolls these short constant-trip loops by itself; forcing it makes compile times explode.
#define SE3_JET_UNROLL
#elif defined(__GNUC__)
#define SE3_JET_UNROLL SE3_JET_PRAGMA(GCC unroll 16)
#else
#define SE3_JET_UNROLL
#endif
#if defined(__GNUC__)
#define SE3_JET_INLINE __attribute__((always_inline)) inline
#else
#define SE3_JET_INLINE inline
#endif

namespace se3_interpolation
{
template <int K>
class Jet
{
public:
  static_assert(K >= 1, "a jet carries at least the first derivative");
  static constexpr int kOrder = K;

  Jet() { c_.fill(0.0); }
  /// Uninitialised coefficients, for results that assign every one.
  struct NoInit
  {};
  explicit Jet(NoInit /*tag*/) {}
  Jet(double value)  // NOLINT(google-explicit-constructor): constants mix with jets
  {
    c_.fill(0.0);
    c_[0] = value;
  }

  /// The jet of the independent variable t at t0: (t0, 1, 0, …).
  static Jet variable(double t0)
  {
    Jet j(t0);
    j.c_[1] = 1.0;
    return j;
  }

  double value() const { return c_[0]; }
  double coefficient(int k) const { return c_[k]; }
  double& coefficient(int k) { return c_[k]; }
  /// The k-th derivative k! c_k.
  double derivative(int k) const
  {
    double factorial = 1.0;
    SE3_JET_UNROLL
    for (int i = 2; i <= k; ++i)
      factorial *= i;
    return factorial * c_[k];
  }

  SE3_JET_INLINE Jet& operator+=(const Jet& o)
  {
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
      c_[k] += o.c_[k];
    return *this;
  }
  SE3_JET_INLINE Jet& operator-=(const Jet& o)
  {
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
      c_[k] -= o.c_[k];
    return *this;
  }
  Jet& operator*=(const Jet& o) { return *this = *this * o; }
  Jet& operator/=(const Jet& o) { return *this = *this / o; }

  friend SE3_JET_INLINE Jet operator+(Jet a, const Jet& b) { return a += b; }
  friend SE3_JET_INLINE Jet operator-(Jet a, const Jet& b) { return a -= b; }

  // Mixed arithmetic with constants: no jet-by-jet product for a scalar factor.
  friend SE3_JET_INLINE Jet operator*(Jet a, double b)
  {
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
      a.c_[k] *= b;
    return a;
  }
  friend SE3_JET_INLINE Jet operator*(double a, Jet b) { return b * a; }
  friend SE3_JET_INLINE Jet operator/(const Jet& a, double b) { return a * (1.0 / b); }
  friend SE3_JET_INLINE Jet operator+(Jet a, double b)
  {
    a.c_[0] += b;
    return a;
  }
  friend SE3_JET_INLINE Jet operator+(double a, Jet b) { return b + a; }
  friend SE3_JET_INLINE Jet operator-(Jet a, double b)
  {
    a.c_[0] -= b;
    return a;
  }
  friend SE3_JET_INLINE Jet operator-(double a, const Jet& b) { return -b + a; }
  friend SE3_JET_INLINE Jet operator-(const Jet& a)
  {
    Jet r{ NoInit{} };
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
      r.c_[k] = -a.c_[k];
    return r;
  }
  friend Jet operator+(const Jet& a) { return a; }
  friend SE3_JET_INLINE Jet operator*(const Jet& a, const Jet& b)
  {
    Jet r{ NoInit{} };
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
    {
      double s = 0.0;
      SE3_JET_UNROLL
      for (int i = 0; i <= k; ++i)
        s += a.c_[i] * b.c_[k - i];
      r.c_[k] = s;
    }
    return r;
  }
  friend SE3_JET_INLINE Jet operator/(const Jet& a, const Jet& b)
  {
    Jet r{ NoInit{} };
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
    {
      double s = a.c_[k];
      SE3_JET_UNROLL
      for (int i = 1; i <= k; ++i)
        s -= b.c_[i] * r.c_[k - i];
      r.c_[k] = s / b.c_[0];
    }
    return r;
  }

  friend bool operator<(const Jet& a, const Jet& b) { return a.c_[0] < b.c_[0]; }
  friend bool operator>(const Jet& a, const Jet& b) { return a.c_[0] > b.c_[0]; }
  friend bool operator<=(const Jet& a, const Jet& b) { return a.c_[0] <= b.c_[0]; }
  friend bool operator>=(const Jet& a, const Jet& b) { return a.c_[0] >= b.c_[0]; }
  friend bool operator==(const Jet& a, const Jet& b) { return a.c_ == b.c_; }
  friend bool operator!=(const Jet& a, const Jet& b) { return !(a == b); }

  friend Jet sqrt(const Jet& a)
  {
    Jet r;
    r.c_[0] = std::sqrt(a.c_[0]);
    SE3_JET_UNROLL
    for (int k = 1; k <= K; ++k)
    {
      double s = a.c_[k];
      SE3_JET_UNROLL
      for (int i = 1; i < k; ++i)
        s -= r.c_[i] * r.c_[k - i];
      r.c_[k] = s / (2.0 * r.c_[0]);
    }
    return r;
  }

  /// sin and cos together (they share one recurrence).
  friend void sincos(const Jet& a, Jet* sine, Jet* cosine)
  {
    Jet& s = *sine;
    Jet& c = *cosine;
    s.c_[0] = std::sin(a.c_[0]);
    c.c_[0] = std::cos(a.c_[0]);
    SE3_JET_UNROLL
    for (int k = 1; k <= K; ++k)
    {
      double ss = 0.0;
      double cc = 0.0;
      SE3_JET_UNROLL
      for (int j = 1; j <= k; ++j)
      {
        ss += j * a.c_[j] * c.c_[k - j];
        cc += j * a.c_[j] * s.c_[k - j];
      }
      s.c_[k] = ss / k;
      c.c_[k] = -cc / k;
    }
  }
  friend Jet sin(const Jet& a)
  {
    Jet s, c;
    sincos(a, &s, &c);
    return s;
  }
  friend Jet cos(const Jet& a)
  {
    Jet s, c;
    sincos(a, &s, &c);
    return c;
  }
  friend Jet tan(const Jet& a)
  {
    Jet s, c;
    sincos(a, &s, &c);
    return s / c;
  }

  /// atan2 through its derivative (x y' − y x') / (x² + y²), integrated term by term.
  friend Jet atan2(const Jet& y, const Jet& x)
  {
    const Jet dy = y.derivativeSeries();
    const Jet dx = x.derivativeSeries();
    const Jet h = (x * dy - y * dx) / (x * x + y * y);
    Jet r;
    r.c_[0] = std::atan2(y.c_[0], x.c_[0]);
    SE3_JET_UNROLL
    for (int k = 1; k <= K; ++k)
      r.c_[k] = h.c_[k - 1] / k;
    return r;
  }

  friend Jet abs(const Jet& a) { return a.c_[0] < 0.0 ? -a : a; }

  friend bool isfinite(const Jet& a)
  {
    for (double v : a.c_)
      if (!std::isfinite(v))
        return false;
    return true;
  }

private:
  /// The series of d/dt (the top coefficient is lost, unused by callers).
  Jet derivativeSeries() const
  {
    Jet d;
    SE3_JET_UNROLL
    for (int k = 0; k < K; ++k)
      d.c_[k] = (k + 1) * c_[k + 1];
    return d;
  }

  std::array<double, K + 1> c_;
};

/// The value of a double or of a jet, for branching on the point of evaluation.
inline double valueOf(double x)
{
  return x;
}
template <int K>
double valueOf(const Jet<K>& x)
{
  return x.value();
}

inline void sincos(double a, double* s, double* c)
{
  *s = std::sin(a);
  *c = std::cos(a);
}

}  // namespace se3_interpolation

namespace Eigen
{
template <int K>
struct NumTraits<se3_interpolation::Jet<K>> : GenericNumTraits<se3_interpolation::Jet<K>>
{
  using Real = se3_interpolation::Jet<K>;
  using NonInteger = se3_interpolation::Jet<K>;
  using Nested = se3_interpolation::Jet<K>;
  using Literal = se3_interpolation::Jet<K>;
  enum
  {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = K + 1,
    AddCost = K + 1,
    MulCost = (K + 1) * (K + 2) / 2
  };
  static inline Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static inline Real dummy_precision() { return Real(1e-12); }
  static inline Real highest() { return Real(std::numeric_limits<double>::max()); }
  static inline Real lowest() { return Real(std::numeric_limits<double>::lowest()); }
  static inline int digits10() { return std::numeric_limits<double>::digits10; }
};

namespace internal
{
/// The Hamilton product of quaternions of jets, coefficient by coefficient:
/// (a b)_k = Σ_{i+j=k} a_i b_j with a_i, b_j the quaternions of doubles formed by the i-th and
/// j-th Taylor coefficients. The same sums as Eigen's generic product, regrouped so that no jet
/// temporaries are formed (the product of two curves' quaternions is the hot spot of sampling
/// derivatives).
template <int Arch, class Derived1, class Derived2, int K>
struct quat_product<Arch, Derived1, Derived2, se3_interpolation::Jet<K>>
{
  using J = se3_interpolation::Jet<K>;
  static SE3_JET_INLINE Quaternion<J> run(const QuaternionBase<Derived1>& a, const QuaternionBase<Derived2>& b)
  {
    J rw{ typename J::NoInit{} }, rx{ typename J::NoInit{} }, ry{ typename J::NoInit{} }, rz{ typename J::NoInit{} };
    SE3_JET_UNROLL
    for (int k = 0; k <= K; ++k)
    {
      double w = 0.0, x = 0.0, y = 0.0, z = 0.0;
      SE3_JET_UNROLL
      for (int i = 0; i <= k; ++i)
      {
        const double aw = a.w().coefficient(i), ax = a.x().coefficient(i), ay = a.y().coefficient(i),
                     az = a.z().coefficient(i);
        const double bw = b.w().coefficient(k - i), bx = b.x().coefficient(k - i), by = b.y().coefficient(k - i),
                     bz = b.z().coefficient(k - i);
        w += aw * bw - ax * bx - ay * by - az * bz;
        x += aw * bx + ax * bw + ay * bz - az * by;
        y += aw * by + ay * bw + az * bx - ax * bz;
        z += aw * bz + az * bw + ax * by - ay * bx;
      }
      rw.coefficient(k) = w;
      rx.coefficient(k) = x;
      ry.coefficient(k) = y;
      rz.coefficient(k) = z;
    }
    return Quaternion<J>(rw, rx, ry, rz);
  }
};
}  // namespace internal

template <int K, typename BinaryOp>
struct ScalarBinaryOpTraits<se3_interpolation::Jet<K>, double, BinaryOp>
{
  using ReturnType = se3_interpolation::Jet<K>;
};
template <int K, typename BinaryOp>
struct ScalarBinaryOpTraits<double, se3_interpolation::Jet<K>, BinaryOp>
{
  using ReturnType = se3_interpolation::Jet<K>;
};
}  // namespace Eigen
