#pragma once
// Closed-form view factors from J. R. Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors" (3rd ed., http://www.thermalradiation.net/indexCat.html), also in
// Howell, Menguc & Siegel, "Thermal Radiation Heat Transfer", 6th ed., appendix C.
#include <cmath>

namespace thermodec::test {

//! C-11: between identical, parallel, directly opposed rectangles a x b at distance c.
inline double parallel_rectangles(double a, double b, double c) {
  const double X = a / c, Y = b / c;
  const double X2 = X * X, Y2 = Y * Y;
  return 2.0 / (M_PI * X * Y) *
         (0.5 * std::log((1 + X2) * (1 + Y2) / (1 + X2 + Y2)) + X * std::sqrt(1 + Y2) * std::atan(X / std::sqrt(1 + Y2)) +
          Y * std::sqrt(1 + X2) * std::atan(Y / std::sqrt(1 + X2)) - X * std::atan(X) - Y * std::atan(Y));
}

//! C-14: from rectangle 1 (width w, common edge l) to rectangle 2 (height h, common edge l),
//! perpendicular and sharing the edge l.
inline double perpendicular_rectangles(double w, double h, double l) {
  const double W = w / l, H = h / l, W2 = W * W, H2 = H * H, S = std::sqrt(H2 + W2);
  const double a = (1 + W2) * (1 + H2) / (1 + W2 + H2);
  const double b = W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2));
  const double c = H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2));
  return 1.0 / (M_PI * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) - S * std::atan(1 / S) +
          0.25 * (std::log(a) + W2 * std::log(b) + H2 * std::log(c)));
}

//! C-41: from disk of radius r1 to a parallel coaxial disk of radius r2 at distance h.
inline double coaxial_disks(double r1, double r2, double h) {
  const double R1 = r1 / h, R2 = r2 / h, X = 1 + (1 + R2 * R2) / (R1 * R1);
  return 0.5 * (X - std::sqrt(X * X - 4 * (R2 / R1) * (R2 / R1)));
}

}  // namespace thermodec::test
