#include "glassmap/geometry/optics.hpp"

#include <algorithm>
#include <cmath>

#include "glassmap/core/angles.hpp"

namespace glassmap {

namespace {

// Incidence folded into [0, pi/2] (a beam at -theta meets the surface like one at +theta).
double foldIncidence(double theta_i) { return std::min(std::abs(theta_i), kPi / 2); }

}  // namespace

std::optional<double> refractionAngle(double theta_i, double n1, double n2) {
  const double s = n1 / n2 * std::sin(foldIncidence(theta_i));
  if (s > 1.0) return std::nullopt;
  return std::asin(s);
}

double criticalAngle(double n1, double n2) { return n2 >= n1 ? kPi / 2 : std::asin(n2 / n1); }

double brewsterAngle(double n1, double n2) { return std::atan2(n2, n1); }

// Paper Fig. 4 (the s-polarised pair), and the p-polarised pair of the same Fresnel equations:
//   r_s = (n1 cos ti - n2 cos tt) / (n1 cos ti + n2 cos tt),  R_s = r_s^2
//   t_s = 2 n1 cos ti / (n1 cos ti + n2 cos tt),             T_s = t_s^2 * n2 cos tt / (n1 cos ti)
//   r_p = (n2 cos ti - n1 cos tt) / (n2 cos ti + n1 cos tt),  R_p = r_p^2
//   t_p = 2 n1 cos ti / (n2 cos ti + n1 cos tt),             T_p = t_p^2 * n2 cos tt / (n1 cos ti)
// T is computed from its own formula (not as 1 - R) so that R + T = 1 is a real check.
Fresnel fresnel(double theta_i, double n1, double n2) {
  Fresnel f;
  const double ti = foldIncidence(theta_i);
  const auto tt = refractionAngle(ti, n1, n2);
  if (!tt) {
    f.r_s = f.r_p = 1.0;
    f.total_internal_reflection = true;
    return f;
  }
  const double ci = std::cos(ti), ct = std::cos(*tt);
  const double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
  const double rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
  f.r_s = rs * rs;
  f.r_p = rp * rp;
  if (ci > 0.0) {  // at grazing incidence (ci = 0) nothing is transmitted
    const double ts = 2 * n1 * ci / (n1 * ci + n2 * ct);
    const double tp = 2 * n1 * ci / (n2 * ci + n1 * ct);
    const double beam = n2 * ct / (n1 * ci);  // change of beam cross-section and speed
    f.t_s = ts * ts * beam;
    f.t_p = tp * tp * beam;
  }
  return f;
}

double reflectance(double theta_i, double n1, double n2) { return fresnel(theta_i, n1, n2).reflectance(); }

double transmittance(double theta_i, double n1, double n2) { return fresnel(theta_i, n1, n2).transmittance(); }

double paneGlassPath(double thickness, double theta_i, double n_glass) {
  // From air into glass theta_t always exists (n_glass >= 1).
  const double tt = refractionAngle(theta_i, kAirIndex, n_glass).value_or(kPi / 2);
  return thickness / std::cos(tt);
}

double paneLateralShift(double thickness, double theta_i, double n_glass) {
  const double ti = foldIncidence(theta_i);
  const double tt = refractionAngle(ti, kAirIndex, n_glass).value_or(kPi / 2);
  return thickness * std::sin(ti - tt) / std::cos(tt);
}

// Range elongation through a pane, derivation.
//
// A time-of-flight sensor reports r = c * (round-trip time) / 2, i.e. the optical length of the
// one-way path: sum of n_k * L_k over the media crossed (the echo comes back the same way).
// Take a pane with parallel faces, thickness t, index n, met at incidence theta_i. Inside, the
// beam runs at theta_t (Snell) for L_glass = t / cos(theta_t) and leaves parallel to its
// original direction, shifted sideways by t sin(theta_i - theta_t) / cos(theta_t).
//
// The map-based expectation d_real is a straight ray cast that ignores the pane. Measure both
// paths up to a surface parallel to the pane at depth D behind the entry face:
//   straight:  D / cos(theta_i)                                     (what d_real is)
//   real:      n t / cos(theta_t) + (D - t) / cos(theta_i)          (what the sensor reports)
// so the reported range is d_real + t (n / cos(theta_t) - 1 / cos(theta_i)), independent of D.
// At normal incidence this is t (n - 1), DESIGN.md's "thickness * (n_glass - 1)". It falls with
// the angle, because the bent beam crosses the pane on a shorter, steeper path than the straight
// ray; it is zero where n cos(theta_i) = cos(theta_t), i.e. tan(theta_i) = n (the Brewster angle,
// 56.3 degrees for n = 1.5), and negative beyond. For a target surface that is not
// parallel to the pane, the sideways shift moves the real hit point along that surface: the
// difference to this formula is at most shift * tan(angle between target and pane), a few mm for
// window glass.
//
// paneOpticalExcess is the other quantity one may want: reported range minus the length of the
// path the light really took, (n - 1) t / cos(theta_t) >= 0, growing with angle and thickness.
double paneRangeElongation(double thickness, double theta_i, double n_glass) {
  const double ti = foldIncidence(theta_i);
  if (thickness == 0.0) return 0.0;
  return n_glass * paneGlassPath(thickness, ti, n_glass) - thickness / std::cos(ti);
}

double paneOpticalExcess(double thickness, double theta_i, double n_glass) {
  return (n_glass - 1.0) * paneGlassPath(thickness, theta_i, n_glass);
}

PaneCrossing crossPane(const Vec2& entry, const Vec2& dir, const Vec2& normal, double thickness, double n_glass) {
  // Orient the normal along the travel direction; split dir into normal and tangential parts.
  const Vec2 nn = dir.dot(normal) >= 0 ? normal : Vec2(-normal);
  const double cos_i = std::min(1.0, dir.dot(nn));
  const Vec2 tangential = dir - cos_i * nn;  // length sin(theta_i)
  const double eta = kAirIndex / n_glass;
  // Snell: sin(theta_t) = eta sin(theta_i), so the tangential part scales by eta.
  const double sin_t2 = eta * eta * tangential.squaredNorm();
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t2));
  const Vec2 inside = cos_t * nn + eta * tangential;  // unit direction in the glass
  PaneCrossing out;
  out.geometric_length = thickness / cos_t;
  out.optical_length = n_glass * out.geometric_length;
  out.exit = entry + out.geometric_length * inside;
  return out;
}

}  // namespace glassmap
