// Orbits around other bodies: the central body's radius, GM, albedo, IR and sun distance reach
// the orbit period, the eclipse, and the absorbed loads (hand values from the NASA fact sheets,
// docs/model-format.md "Central bodies").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "environment/test_models.h"
#include "thermodec/common/errors.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/environment/orbit.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
using namespace thermodec::testing;

namespace {
constexpr double kPi = 3.14159265358979323846;
// Mars at 400 km, by hand: R = 3389.5 km, GM = 42828 km^3/s^2, d = 227.956 / 149.598 AU,
// Bond albedo 0.25, IR = (1 - 0.25) S / 4.
constexpr double kMarsR = 3389.5e3, kMarsGM = 42828.0e9, kMarsD = 227.956 / 149.598;

ThermalModel mars_cube(Attitude attitude) {
  ThermalModel model = model_with({"px", "mx", "py", "my", "pz", "mz"}, {{"paint", 0.5, 0.8}});
  add_cube(model.mesh, 0.5, {0, 1, 2, 3, 4, 5});
  model.environment.type = EnvironmentType::orbit;
  set_central_body(model.environment, *find_central_body("mars"));
  model.environment.altitude_km = 400.0;
  model.environment.attitude = attitude;
  model.analysis.steps_per_orbit = 24;
  return model;
}

Loads loads_of(const ThermalModel& model) {
  const RayScene scene(model.mesh);
  const SurfaceSides sides = surface_sides(model);
  return external_loads(model, scene, sides, nullptr, {});
}
}  // namespace

TEST(CentralBody, mars_orbit_period_flux_and_eclipse_match_hand_values) {
  const ThermalModel model = mars_cube(Attitude::nadir);
  const double r = kMarsR + 400e3;
  EXPECT_DOUBLE_EQ(orbit_period_s(model.environment), 2.0 * kPi * std::sqrt(r * r * r / kMarsGM));
  EXPECT_NEAR(orbit_period_s(model.environment), 7082.5, 0.1);  // vs 5553 s for the Earth at 400 km
  const double S = 1367.0 / (kMarsD * kMarsD);
  EXPECT_NEAR(solar_flux_W_per_m2(model.environment), 588.73, 0.01);
  EXPECT_DOUBLE_EQ(solar_flux_W_per_m2(model.environment), S);
  EXPECT_NEAR(model.environment.earth_ir_flux_W_per_m2, 0.75 * S / 4.0, 1e-9);
  EXPECT_EQ(model.environment.albedo, 0.25);
  // Eclipse of a cylinder of Mars' radius, from the same closed form the Earth's uses.
  Environment env = model.environment;
  const double beta = beta_angle_rad(env), h = r - kMarsR;
  const double f = std::abs(beta) < std::asin(kMarsR / r) ? std::acos(std::sqrt(h * h + 2 * kMarsR * h) / (r * std::cos(beta))) / kPi : 0.0;
  EXPECT_NEAR(eclipse_fraction(env), f, 1e-12);
  const Loads l = loads_of(model);
  EXPECT_DOUBLE_EQ(l.period_s, orbit_period_s(model.environment));
  int dark = 0;
  for (int k = 0; k < l.num_steps(); ++k) dark += l.in_shadow[k];
  EXPECT_NEAR(dark / 24.0, f, 2.0 / 24);
}

TEST(CentralBody, mars_ir_and_sun_on_a_cube_match_hand_values) {
  // Nadir: +Z faces Mars' centre, F = (R / r)^2 = 0.80003; IR absorbed = eps q F A.
  const Loads nadir = loads_of(mars_cube(Attitude::nadir));
  const double r = kMarsR + 400e3, F = std::pow(kMarsR / r, 2), q = 0.75 * 1367.0 / (kMarsD * kMarsD) / 4.0;
  EXPECT_NEAR(nadir.earth_ir_W(4, 0), 0.8 * q * F, 0.8 * q * F * 2e-3);  // as the Earth's test: ~1/N
  EXPECT_NEAR(0.8 * q * F, 70.65, 0.01);
  // Sun pointing: +X faces the sun, absorbed alpha S A on every sunlit step (convex cube).
  const Loads sun = loads_of(mars_cube(Attitude::sun));
  const double S = 1367.0 / (kMarsD * kMarsD);
  for (int k = 0; k < sun.num_steps(); ++k)
    if (!sun.in_shadow[k]) EXPECT_NEAR(sun.solar_W(0, k), 0.5 * S, 1e-9 * S) << k;
}

TEST(CentralBody, model_file_names_a_body_or_gives_its_numbers_and_saving_keeps_it) {
  const auto dir = std::filesystem::temp_directory_path() / "thermodec_central_body_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "m.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\ng a\nf 1 2 3\n";
  auto write = [&](const std::string& env) {
    std::ofstream(dir / "m.json") << R"({"mesh": "m.obj", "materials": {"p": {"absorptivity": 0.5, "emissivity": 0.5}},
      "environment": {"type": "orbit", "altitude_km": 400, )" << env << "}}";
    return load_model(dir / "m.json");
  };
  ThermalModel m = write(R"("central_body": "mars")");
  EXPECT_EQ(m.environment.central_body, "mars");
  EXPECT_EQ(m.environment.body_radius_m, kMarsR);
  EXPECT_EQ(m.environment.albedo, 0.25);
  m = write(R"("central_body": "moon", "albedo": 0.12)");
  EXPECT_EQ(m.environment.body_gravitational_parameter_m3_per_s2, 4902.8e9);
  EXPECT_EQ(m.environment.albedo, 0.12);  // the key overrides the body's
  save_model(m, dir / "saved.json", dir / "saved.obj");
  const ThermalModel back = load_model(dir / "saved.json");
  EXPECT_EQ(central_body_of(back.environment), central_body_of(m.environment));
  m = write(R"("central_body": {"name": "ceres", "radius_km": 469.7, "gm_km3_per_s2": 62.6, "albedo": 0.09, "ir_flux": 150, "sun_distance_au": 2.77})");
  EXPECT_EQ(m.environment.body_radius_m, 469.7e3);
  save_model(m, dir / "saved.json", dir / "saved.obj");
  EXPECT_EQ(central_body_of(load_model(dir / "saved.json").environment), central_body_of(m.environment));
  EXPECT_THROW(write(R"("central_body": "venus")"), InvalidInput);
  EXPECT_THROW(write(R"("central_body": {"name": "ceres", "radius_km": 469.7})"), InvalidInput);
  std::filesystem::remove_all(dir);
}
