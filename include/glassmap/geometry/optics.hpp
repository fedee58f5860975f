#pragma once
/// Glass optics for a laser beam: Fresnel reflectance/transmittance (paper Fig. 4), Snell
/// refraction and the range a time-of-flight sensor reports through a pane.
///
/// Angles in radians, measured from the surface normal; n1 is the refractive index of the medium
/// the beam comes from, n2 of the medium it enters. All functions are pure.

#include <optional>

#include "glassmap/core/pose2.hpp"

namespace glassmap {

/// Refractive index of window glass (soda-lime, near-infrared) [-].
inline constexpr double kGlassIndex = 1.5;
/// Refractive index of air [-].
inline constexpr double kAirIndex = 1.0;

/// Refraction angle theta_t [rad] by Snell's law n1 sin(theta_i) = n2 sin(theta_t);
/// std::nullopt on total internal reflection (n1 sin(theta_i) > n2).
std::optional<double> refractionAngle(double theta_i, double n1 = kAirIndex, double n2 = kGlassIndex);

/// Critical angle [rad] for total internal reflection going from n1 into n2 < n1
/// (pi/2 when n2 >= n1: no total internal reflection).
double criticalAngle(double n1 = kGlassIndex, double n2 = kAirIndex);

/// Brewster angle [rad]: where the p-polarised reflectance vanishes, tan(theta_B) = n2 / n1.
double brewsterAngle(double n1 = kAirIndex, double n2 = kGlassIndex);

/// Fraction of power of one interface crossing, by polarisation.
struct Fresnel {
  double r_s = 0.0;                        ///< reflectance, s-polarised (the paper's "Reflectance", Fig. 4) [-]
  double r_p = 0.0;                        ///< reflectance, p-polarised [-]
  double t_s = 0.0;                        ///< transmittance, s-polarised (the paper's "Transmittance") [-]
  double t_p = 0.0;                        ///< transmittance, p-polarised [-]
  bool total_internal_reflection = false;  ///< n1 sin(theta_i) > n2: r = 1, t = 0
  double reflectance() const { return 0.5 * (r_s + r_p); }    ///< unpolarised [-]
  double transmittance() const { return 0.5 * (t_s + t_p); }  ///< unpolarised [-]
};

/// Fresnel power coefficients at incidence theta_i in [0, pi/2] [rad] (paper Fig. 4).
Fresnel fresnel(double theta_i, double n1 = kAirIndex, double n2 = kGlassIndex);

/// Unpolarised reflectance of one air/glass interface at incidence theta_i [rad] [-].
double reflectance(double theta_i, double n1 = kAirIndex, double n2 = kGlassIndex);
/// Unpolarised transmittance of one interface, 1 - reflectance() [-].
double transmittance(double theta_i, double n1 = kAirIndex, double n2 = kGlassIndex);

/// Geometric path length inside a pane of thickness t [m] at incidence theta_i [rad]:
/// t / cos(theta_t) [m].
double paneGlassPath(double thickness, double theta_i, double n_glass = kGlassIndex);

/// Lateral shift of a beam through a parallel-faced pane [m]:
/// t sin(theta_i - theta_t) / cos(theta_t). The beam leaves parallel to how it came in.
double paneLateralShift(double thickness, double theta_i, double n_glass = kGlassIndex);

/// Range elongation through a pane [m]: reported range minus the straight-line range a map
/// ray cast gives (d_real) to a surface parallel to the pane. t (n / cos(theta_t) - 1 / cos(theta_i)).
/// Equals t (n - 1) at normal incidence, falls with the angle and is negative beyond the
/// Brewster angle (derivation in optics.cpp).
double paneRangeElongation(double thickness, double theta_i, double n_glass = kGlassIndex);

/// Extra reported range over the length of the path the light really takes [m]:
/// (n - 1) t / cos(theta_t). Never negative; grows with thickness and angle.
double paneOpticalExcess(double thickness, double theta_i, double n_glass = kGlassIndex);

/// A beam after crossing a parallel-faced pane.
struct PaneCrossing {
  Vec2 exit = Vec2::Zero();     ///< point where the beam leaves the back face [m]
  double optical_length = 0;    ///< n * path inside the glass: what time-of-flight counts [m]
  double geometric_length = 0;  ///< path inside the glass [m]
};

/// Traces a beam with unit direction `dir` entering a pane at `entry` (a point of the face it
/// meets); the pane's faces are perpendicular to unit `normal` (either sign) and `thickness`
/// apart [m], the glass lying on the far side of the entry face. The beam leaves parallel to `dir`.
PaneCrossing crossPane(const Vec2& entry, const Vec2& dir, const Vec2& normal, double thickness,
                       double n_glass = kGlassIndex);

}  // namespace glassmap
