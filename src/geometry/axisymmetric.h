// capflow/geometry/axisymmetric: closed axisymmetric surfaces given by a meridian profile, with
// their area, volume and curvatures computed in long double from the profile alone (1-D
// Gauss-Legendre quadrature and closed-form derivatives), independently of the spectral mesh:
// the reference against which the mesh's own geometry of these shapes is measured.
//
// The profile, theta in [0, pi/2] from the pole to the rim (the other half mirrored in z = 0):
//   r(theta) = R sin(theta),   z(theta) = cos(theta) Q(sin^2 theta),   Q(s) = q0 + q1 s + q2 s^2,
// all lengths times `scale`. A spheroid with equatorial radius R and polar semi-axis c is Q = c;
// the Evans & Fung (1972) red blood cell is R = R0, q_i = c_i / 2 (method.md sec. 10).
// Curvatures with the outward normal, H = +1/R on a sphere (the convention of surface.h):
//   kappa_meridian = -(r' z'' - z' r'') / |v|^3,  kappa_parallel = (Q - 2 cos^2 Q_s) / (R |v|),
//   |v| = sqrt(r'^2 + z'^2),  H = (kappa_m + kappa_p) / 2,  K = kappa_m kappa_p
// (kappa_parallel = -z' / (r |v|) divided out exactly, so the pole needs no limit).
// Area 2 INT 2 pi r |v| dtheta, volume 2 INT 2 pi r z r' dtheta (cylindrical shells), both
// with smooth integrands in theta: the quadrature converges exponentially.
#pragma once

namespace capflow::geometry {

struct AxisymmetricProfile {
  long double R = 1, q0 = 1, q1 = 0, q2 = 0;
  long double scale = 1;
};

struct ProfilePoint {
  long double r = 0, z = 0;  // scaled
  long double H = 0, K = 0;  // 1/length, 1/length^2 (scaled)
};

ProfilePoint profile_point(const AxisymmetricProfile& p, long double theta);
// Lap_s H at theta (1/length^3): (1/(r |v|)) d/dtheta (r/|v| dH/dtheta), dH/dtheta and the outer
// derivative by 8th-order central differences in long double (step 1e-3: ~1e-11 relative);
// theta in (0, pi/2) (the pole and the rim are limits it does not take).
long double profile_laplacian_H(const AxisymmetricProfile& p, long double theta);
// n-point Gauss-Legendre in theta (n = 48 is at the long double round-off for the shapes here).
long double profile_area(const AxisymmetricProfile& p, int n = 48);
long double profile_volume(const AxisymmetricProfile& p, int n = 48);

// The Evans & Fung red blood cell in micrometres: R0 = 3.91, c0 = 0.81, c1 = 7.83, c2 = -4.39.
AxisymmetricProfile evans_fung_profile();
// A spheroid: equatorial radius `equatorial`, polar semi-axis `polar`.
AxisymmetricProfile spheroid_profile(long double equatorial, long double polar);
// The same profile scaled so that it encloses the volume of the unit sphere (4 pi / 3): lengths
// in units of the equal-volume radius a.
AxisymmetricProfile scaled_to_unit_volume(AxisymmetricProfile p);
// The equal-volume radius of the unscaled profile (Evans & Fung: 2.8215 um).
long double equal_volume_radius(const AxisymmetricProfile& p);

}  // namespace capflow::geometry
