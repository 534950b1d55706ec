#pragma once
//! The body an orbit environment circles: its size, gravity, the sunlight it reflects and the
//! infrared it emits, and its distance from the sun. Values and sources: docs/model-format.md,
//! "Central bodies". A new body is one row of central_bodies().
#include <string>
#include <vector>

namespace thermodec {

struct CentralBody {
  std::string name = "earth";
  double radius_m = 6371.0e3;                                 //!< volumetric mean radius R [m]
  double gravitational_parameter_m3_per_s2 = 3.986004418e14;  //!< GM [m^3/s^2]
  double albedo = 0.30;                                       //!< Bond albedo, [0, 1]
  double ir_flux_W_per_m2 = 237.0;                            //!< emitted IR at its surface [W/m^2]
  //! Distance from the sun [AU] that sets the solar flux (solar constant / d^2); 0 = the
  //! Earth's distance on the environment's day of year (the Earth and the Moon).
  double sun_distance_au = 0.0;
  bool operator==(const CentralBody& o) const {
    return name == o.name && radius_m == o.radius_m && gravitational_parameter_m3_per_s2 == o.gravitational_parameter_m3_per_s2 &&
           albedo == o.albedo && ir_flux_W_per_m2 == o.ir_flux_W_per_m2 && sun_distance_au == o.sun_distance_au;
  }
  bool operator!=(const CentralBody& o) const { return !(*this == o); }
};

//! The known bodies: earth (the default of CentralBody), moon, mars, from the NASA planetary fact
//! sheets (radius, GM, Bond albedo, semi-major axis); IR flux of the Moon and Mars from the global
//! energy balance (1 - albedo) S / 4 at 1367 W/m^2 / d^2.
const std::vector<CentralBody>& central_bodies();

//! The row of central_bodies() named `name`, or nullptr.
const CentralBody* find_central_body(const std::string& name);

}  // namespace thermodec
