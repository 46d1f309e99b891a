// Per-coordinate losses of CUT_PURSUIT.md §1.1 (s == 0 linear, s == 1 quadratic, else smoothed KL),
// shared by cut pursuit, its PFDR and the exact solver so all report the same objective.
#pragma once
#include <cmath>

namespace al {

struct Loss {
  double s = 0.1;  // smoothing in [0, 1]
  int D = 2;       // number of labels (q = s / D)

  bool linear() const { return s == 0.0; }
  bool quadratic() const { return s == 1.0; }
  double q() const { return s / D; }
  double c() const { return 1.0 - s; }

  // Value of coordinate d's term at (y_d, x_d), unweighted.
  double Value(double y, double x) const {
    if (linear()) return -x * y;
    if (quadratic()) return 0.5 * (x - y) * (x - y);
    const double yh = q() + c() * y, xh = q() + c() * x;
    return yh > 0.0 ? yh * std::log(yh / xh) : 0.0;
  }
  // d/dx of the coordinate term.
  double Grad(double y, double x) const {
    if (linear()) return -y;
    if (quadratic()) return x - y;
    return -(q() + c() * y) / (q() / c() + x);
  }
  // d^2/dx^2 of the coordinate term.
  double Hess(double y, double x) const {
    if (linear()) return 0.0;
    if (quadratic()) return 1.0;
    const double xh = q() + c() * x;
    return c() * c() * (q() + c() * y) / (xh * xh);
  }
  // Lipschitz bound of Grad on x in [0, 1] (worst case x = 0).
  double Lipschitz(double y) const {
    if (linear()) return 0.0;
    if (quadratic()) return 1.0;
    const double r = c() / q();
    return r * r * (q() + c() * y);
  }
};

}  // namespace al
