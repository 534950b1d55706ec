// Central bodies of orbit environments. Sources (docs/model-format.md, "Central bodies"):
// NASA NSSDCA planetary fact sheets (Williams, nssdc.gsfc.nasa.gov/planetary/factsheet):
// volumetric mean radius, GM, Bond albedo, semi-major axis (Mars 227.956e6 km / 1 AU
// 149.598e6 km = 1.52379 AU). The Earth's albedo 0.30 and IR 237 W/m^2 are the usual
// orbit-average design values (Gilmore, Spacecraft Thermal Control Handbook, 2002, ch. 2).
// The Moon's and Mars' IR is the uniform emission that balances the absorbed sunlight,
// (1 - A) S / 4: the Moon's real IR ranges from ~5 W/m^2 (night) to ~1300 W/m^2 (subsolar),
// which a uniformly emitting sphere does not represent.
#include "thermodec/nodes/central_body.h"

namespace thermodec {

namespace {
constexpr double kSolarConstant_W_per_m2 = 1367.0;  // as environment/orbit.h
constexpr double kMarsDistance_au = 227.956 / 149.598;
}  // namespace

const std::vector<CentralBody>& central_bodies() {
  static const std::vector<CentralBody> table{
      CentralBody{},  // earth
      {"moon", 1737.4e3, 4902.8e9, 0.11, (1.0 - 0.11) * kSolarConstant_W_per_m2 / 4.0, 0.0},
      {"mars", 3389.5e3, 42828.0e9, 0.25,
       (1.0 - 0.25) * kSolarConstant_W_per_m2 / (kMarsDistance_au * kMarsDistance_au) / 4.0, kMarsDistance_au},
  };
  return table;
}

const CentralBody* find_central_body(const std::string& name) {
  for (const CentralBody& b : central_bodies())
    if (b.name == name) return &b;
  return nullptr;
}

}  // namespace thermodec
