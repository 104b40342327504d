#include "geometry/axisymmetric.h"

#include <cmath>
#include <utility>
#include <vector>

namespace capflow::geometry {

namespace {

using LD = long double;
const LD kPi = 3.141592653589793238462643383279502884L;

// Gauss-Legendre nodes and weights on [-1, 1] in long double (Newton on P_n from Chebyshev
// guesses), independent of spectral/'s double-precision rules.
std::vector<std::pair<LD, LD>> gauss_legendre_ld(int n) {
  std::vector<std::pair<LD, LD>> r(n);
  for (int i = 0; i < n; ++i) {
    LD x = std::cos(kPi * (i + 0.75L) / (n + 0.5L));
    LD dp = 0;
    for (int it = 0; it < 100; ++it) {
      LD p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const LD p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const LD dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-19L) break;
    }
    r[i] = {x, 2 / ((1 - x * x) * dp * dp)};
  }
  return r;
}

struct Derivs {
  LD r, r1, r2, z, z1, z2, Q, Qs;
};

Derivs derivs(const AxisymmetricProfile& p, LD th) {
  const LD s = std::sin(th), c = std::cos(th);
  const LD u = s * s, u1 = 2 * s * c, u2 = 2 * (c * c - s * s);
  const LD Q = p.q0 + p.q1 * u + p.q2 * u * u, Qs = p.q1 + 2 * p.q2 * u, Qss = 2 * p.q2;
  Derivs d;
  d.r = p.R * s;
  d.r1 = p.R * c;
  d.r2 = -p.R * s;
  d.z = c * Q;
  d.z1 = -s * Q + c * Qs * u1;
  d.z2 = -c * Q - 2 * s * Qs * u1 + c * (Qss * u1 * u1 + Qs * u2);
  d.Q = Q;
  d.Qs = Qs;
  return d;
}

template <class F>
LD integrate(int n, F f) {  // INT_0^{pi/2} f(theta) dtheta
  LD sum = 0;
  for (const auto& [x, w] : gauss_legendre_ld(n)) sum += w * f(kPi / 4 * (x + 1));
  return sum * kPi / 4;
}

}  // namespace

ProfilePoint profile_point(const AxisymmetricProfile& p, long double theta) {
  const Derivs d = derivs(p, theta);
  const LD v = std::sqrt(d.r1 * d.r1 + d.z1 * d.z1);
  const LD km = -(d.r1 * d.z2 - d.z1 * d.r2) / (v * v * v);
  const LD c = std::cos(theta);
  const LD kp = (d.Q - 2 * c * c * d.Qs) / (p.R * v);
  ProfilePoint q;
  q.r = d.r * p.scale;
  q.z = d.z * p.scale;
  q.H = (km + kp) / 2 / p.scale;
  q.K = km * kp / (p.scale * p.scale);
  return q;
}

namespace {

// 8th-order central difference of f at t with step h.
template <class F>
LD central(F f, LD t, LD h) {
  static const LD c[4] = {4.0L / 5, -1.0L / 5, 4.0L / 105, -1.0L / 280};
  LD s = 0;
  for (int k = 1; k <= 4; ++k) s += c[k - 1] * (f(t + k * h) - f(t - k * h));
  return s / h;
}

}  // namespace

long double profile_laplacian_H(const AxisymmetricProfile& p, long double theta) {
  const LD h = 1e-3L;
  const auto speed = [&](LD th) {
    const Derivs d = derivs(p, th);
    return std::sqrt(d.r1 * d.r1 + d.z1 * d.z1) * p.scale;
  };
  const auto H = [&](LD th) { return profile_point(p, th).H; };
  const auto flux = [&](LD th) {
    return profile_point(p, th).r / speed(th) * central(H, th, h);
  };
  return central(flux, theta, h) / (profile_point(p, theta).r * speed(theta));
}

long double profile_area(const AxisymmetricProfile& p, int n) {
  return 2 * p.scale * p.scale * integrate(n, [&](LD th) {
           const Derivs d = derivs(p, th);
           return 2 * kPi * d.r * std::sqrt(d.r1 * d.r1 + d.z1 * d.z1);
         });
}

long double profile_volume(const AxisymmetricProfile& p, int n) {
  return 2 * p.scale * p.scale * p.scale * integrate(n, [&](LD th) {
           const Derivs d = derivs(p, th);
           return 2 * kPi * d.r * d.z * d.r1;
         });
}

AxisymmetricProfile evans_fung_profile() {
  AxisymmetricProfile p;
  p.R = 3.91L;
  p.q0 = 0.81L / 2;
  p.q1 = 7.83L / 2;
  p.q2 = -4.39L / 2;
  return p;
}

AxisymmetricProfile spheroid_profile(long double equatorial, long double polar) {
  AxisymmetricProfile p;
  p.R = equatorial;
  p.q0 = polar;
  return p;
}

long double equal_volume_radius(const AxisymmetricProfile& p) {
  AxisymmetricProfile u = p;
  u.scale = 1;
  return std::cbrt(3 * profile_volume(u) / (4 * kPi));
}

AxisymmetricProfile scaled_to_unit_volume(AxisymmetricProfile p) {
  p.scale = 1 / equal_volume_radius(p);
  return p;
}

}  // namespace capflow::geometry
