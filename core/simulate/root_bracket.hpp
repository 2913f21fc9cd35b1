// A root of a scalar function bracketed to a given width by regula falsi with the
// Anderson-Björck modification, for event localization on a cheap interpolant (core/simulate/model_propagator.hpp).
//
// Why not Boost.Math's toms748 (used on RK4 re-steps): on a step's cubic interpolant one
// evaluation costs a few nanoseconds, and toms748's own arithmetic (its quadratic and cubic
// interpolation steps, about 0.1 µs per localization) was then most of the time. Regula falsi
// needs one division per point. The Anderson-Björck rule (Anderson & Björck, BIT 12, 1973):
// when the same end is kept twice in a row, its value is scaled by m = 1 - f(c)/f(new end), or
// by 1/2 when m <= 0; this avoids plain regula falsi's one-sided stagnation and converges
// superlinearly (on the chasing cars' shift guards: 4.0 evaluations per localization to 1e-12 s,
// against 4.9 with Illinois' fixed 1/2, and 4.8 for toms748 on re-steps). Where f is a known
// cubic (an affine guard along the interpolant), bracket_cubic_root's Newton steps need fewer
// divisions still: 1.4 steps after the secant estimate, and two evaluations to confirm.
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>

namespace hyfal {

// A root of f in (a, b], where f(a) <= 0 < f(b), as a bracket [a', b'] with
// a <= a' < b' <= b, b' - a' <= tol and f(a') <= 0 < f(b') (a' = a or b' = b where f was not
// evaluated). Each point is kept at least tol/2 inside the current bracket, so once a point
// lands (numerically) on the root the next lands on its other side and closes the bracket.
// At most max_evaluations calls of f; the bracket reached then is returned.
template <class F>
std::pair<double, double> bracket_root(F&& f, double a, double b, double fa, double fb, double tol,
                                       int max_evaluations = 200) {
  // The next point is the secant through (a, fa) and (b, fb) after the scaling, written with
  // one division: the scaled value (fa m, m = (fb_old - fc)/fb_old) enters the secant as the
  // numerator over fb_old, so the scaling's own division runs beside it, not before it (a
  // division's latency per point: the loop is one chain of dependent operations).
  const double half = 0.5 * tol;
  double c = b - fb * (b - a) / (fb - fa);  // plain regula falsi first
  int kept = 0;                             // +1: b was replaced last, -1: a was
  for (int i = 0; i < max_evaluations && b - a > tol; ++i) {
    if (!(c >= a + half)) c = c < a + half ? a + half : 0.5 * (a + b);  // NaN: the midpoint
    if (c > b - half) c = b - half;
    const double fc = f(c);
    if (fc > 0.0) {
      if (kept == 1 && fb - fc > 0.0) {  // a kept twice: fa scaled by m = (fb - fc)/fb > 0
        const double num = fa * (fb - fc), next = c - fc * (c - a) * fb / (fc * fb - num);
        fa = num / fb;
        b = c, fb = fc, c = next;
      } else {
        if (kept == 1) fa *= 0.5;  // m <= 0
        b = c, fb = fc;
        c = b - fb * (b - a) / (fb - fa);
      }
      kept = 1;
    } else {
      if (kept == -1 && fa - fc < 0.0) {  // b kept twice: fb scaled by m = (fa - fc)/fa > 0
        const double num = fb * (fa - fc), next = c - fc * (c - b) * fa / (fc * fa - num);
        fb = num / fa;
        a = c, fa = fc, c = next;
      } else {
        if (kept == -1) fb *= 0.5;  // m <= 0
        a = c, fa = fc;
        c = b - fb * (b - a) / (fb - fa);
      }
      kept = -1;
    }
  }
  return {a, b};
}

// bracket_root() for the cubic p(x) = c0 + x (c1 + x (c2 + x c3)): Newton's method from the
// secant estimate, whose chain of dependent operations has one division per step where the
// regula falsi has one per point and needs more points. After a step s from x, Newton's error
// is about |p''| s² / (2 |p'|); once that is below tol/10 the root lies far inside
// [x - 0.4 tol, x + 0.4 tol], which is checked by two evaluations and returned (on the chasing
// cars' shift guards: 1.4 steps per localization). A step leaving (a, b), a flat p', no bracket
// within 6 steps hands over to bracket_root(), so the contract is bracket_root's.
inline std::pair<double, double> bracket_cubic_root(double c0, double c1, double c2, double c3, double a, double b,
                                                    double fa, double fb, double tol) {
  const auto p = [&](double x) { return c0 + x * (c1 + x * (c2 + x * c3)); };
  if (b - a > tol) {
    const double d1 = 2.0 * c2, d2 = 3.0 * c3;
    double x = b - fb * (b - a) / (fb - fa);
    for (int i = 0; i < 6 && x > a && x < b; ++i) {
      const double slope = c1 + x * (d1 + x * d2), curvature = d1 + 2.0 * d2 * x;  // p', p''
      const double step = p(x) / slope;
      x -= step;
      if (std::abs(curvature) * step * step <= 0.2 * tol * std::abs(slope)) {
        const double lo = std::max(a, x - 0.4 * tol), hi = std::min(b, x + 0.4 * tol);
        if (lo < hi && (lo == a ? fa : p(lo)) <= 0.0 && (hi == b ? fb : p(hi)) > 0.0) return {lo, hi};
      }
    }
  }
  return bracket_root(p, a, b, fa, fb, tol);
}

}  // namespace hyfal
