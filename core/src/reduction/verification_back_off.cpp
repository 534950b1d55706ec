#include "thermodec/reduction/verification_back_off.h"

namespace thermodec {

double back_off_scale(int steps, const std::function<bool(double)>& accepts) {
  double good = 0.0, bad = 1.0;
  for (int k = 0; k < steps; ++k) {
    const double s = 0.5 * (good + bad);
    if (accepts(s)) good = s;
    else bad = s;
  }
  return good;
}

}  // namespace thermodec
