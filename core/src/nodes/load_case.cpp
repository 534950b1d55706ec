#include "thermodec/nodes/load_case.h"

#include "model_json.h"

namespace thermodec {
namespace fs = std::filesystem;
using namespace model_json;

LoadCase own_case(const ThermalModel& model, const std::string& name) {
  return LoadCase{name, model.environment, model.analysis};
}

LoadCase load_case(const fs::path& path, const ThermalModel& base) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IOError(path.string() + ": no such file");
  const Keys k(path.string());
  const json j = read_json(path);
  k.require_object(j, "");
  k.only_keys(j, "", {"name", "description", "environment", "analysis"}, " in a load case file");
  LoadCase c = own_case(base, path.stem().string());
  if (j.contains("name")) c.name = k.string(j, "", "name");
  if (j.contains("environment")) parse_environment(j.at("environment"), k, c.environment);
  if (j.contains("analysis")) parse_analysis(j.at("analysis"), k, c.analysis);
  check_analysis_fits_environment(c.analysis, c.environment, k);
  return c;
}

ThermalModel with_case(const ThermalModel& model, const LoadCase& c) {
  ThermalModel m = model;
  m.environment = c.environment;
  m.analysis = c.analysis;
  // As the model file's own check (check_internal_power), before any work on the case.
  check_internal_power(m, Keys("load case '" + c.name + "'", false));
  return m;
}

}  // namespace thermodec
