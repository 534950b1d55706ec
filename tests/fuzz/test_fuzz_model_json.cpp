// Mutation fuzzing of the model file and load case readers (nodes/load_model.h, nodes/load_case.h)
// in-process: every input is loaded as a valid model (or case) or refused with a
// thermodec::Error (fuzz_harness.h). Half of the inputs are byte mutations of the JSON text,
// half are structural: a value replaced by one of another type, an extreme or a non-finite
// number, a key deleted, misspelt or repeated.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fuzz/fuzz_harness.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

const fs::path kData = THERMODEC_TEST_DATA_DIR;
const fs::path kSample = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";

// Inputs per reader: 1 to 5 s each in a Release build on one core (files in /dev/shm).
constexpr int kIterations = 12000;

// Pointers to every value of `j` (objects and arrays included), in document order.
void values(json& j, std::vector<json*>& out) {
  out.push_back(&j);
  if (j.is_structured())
    for (auto& v : j) values(v, out);
}

// One structural mutation of a JSON document, serialised; the serialiser escapes what it
// must, so the byte mutations are what exercise the parser itself.
std::string mutate_structure(const std::string& text, fuzz::Rng& rng) {
  json j = json::parse(text);
  for (std::size_t k = 1 + rng.below(3); k > 0; --k) {
    std::vector<json*> all;
    values(j, all);
    json& v = *all[rng.below(all.size())];
    const json replacements[] = {nullptr, true, -1, 0, 1, 3, 0.5, -273.2, 1e308, -1e308, 4.9e-324, 2147483648LL,
                                 -2147483649LL, 18446744073709551615ULL, 1e6, 1e7 + 1, "x", "", json::array(),
                                 json::object(), json::array({1, 2}), json::array({0, 0, 0}), "\u00e9\t\n"};
    const std::size_t choice = rng.below(std::size(replacements) + 3);
    if (choice < std::size(replacements)) {
      v = replacements[choice];
    } else if (v.is_object() && !v.empty()) {
      // Delete, misspell or duplicate (a repeated key, in the text) one member.
      auto it = v.begin();
      std::advance(it, rng.below(v.size()));
      const std::string key = it.key();
      if (choice == std::size(replacements)) {
        v.erase(key);
      } else if (choice == std::size(replacements) + 1) {
        json moved = *it;
        v.erase(key);
        v[key.substr(0, key.size() / 2) + "x" + key.substr(key.size() / 2)] = moved;
      } else {
        std::string out = j.dump();
        const std::string member = "\"" + key + "\":";
        const std::size_t at = out.find(member);
        if (at != std::string::npos) out.insert(at, member + "0,");
        return out;
      }
    }
  }
  return j.dump(rng.chance(0.5) ? 1 : -1);
}

// Documented ranges a loaded model must satisfy (docs/model-format.md).
std::string model_problem(const ThermalModel& m) {
  std::string p = fuzz::mesh_problem(m.mesh);
  if (!p.empty()) return p;
  const int nodes = static_cast<int>(m.nodes.size()), materials = static_cast<int>(m.materials.size());
  for (int f = 0; f < m.mesh.num_faces(); ++f)
    if (m.mesh.face_node[f] < 0 || m.mesh.face_node[f] >= nodes || m.mesh.face_material[f] < 0 ||
        m.mesh.face_material[f] >= materials)
      return "face " + std::to_string(f) + " without a resolved node or material";
  for (const Material& x : m.materials)
    if (!(x.absorptivity > 0 && x.absorptivity <= 1 && x.emissivity > 0 && x.emissivity <= 1))
      return "material " + x.name + " out of (0, 1]";
  for (const Node& n : m.nodes) {
    if (!(std::isfinite(n.capacitance_J_per_K) && n.capacitance_J_per_K >= 0 && std::isfinite(n.power_W)))
      return "node " + n.name + ": capacitance or power";
    if (n.fixed_temperature_K && !(std::isfinite(*n.fixed_temperature_K) && *n.fixed_temperature_K >= 1))
      return "node " + n.name + ": fixed temperature";
  }
  for (const Conductance& c : m.conductances)
    if (c.from < 0 || c.from >= nodes || c.to < 0 || c.to >= nodes || !std::isfinite(c.conductance_W_per_K))
      return "a conductance with a bad node or value";
  if (!(std::isfinite(m.unit_scale) && m.unit_scale > 0)) return "unit_scale";
  if (m.default_material < 0 || m.default_material >= materials) return "default_material";
  const Analysis& a = m.analysis;
  if (a.steps_per_orbit < 4 || a.steps_per_orbit > 1000000 || a.orbits < 1 || !(a.time_tolerance_K > 0))
    return "analysis out of range";
  if (m.radiation.rays_per_face < 1 || m.radiation.min_rays_per_node < 0) return "radiation out of range";
  const Environment& e = m.environment;
  if (!(e.altitude_km > 0 && std::isfinite(e.altitude_km)) || !e.sun_direction.allFinite() ||
      !(std::abs(e.sun_direction.norm() - 1.0) < 1e-9) || e.day_of_year < 1 || e.day_of_year > 366)
    return "environment out of range";
  return {};
}

// Mutations of `corpus` texts: half structural, half bytes (of the text or of a structural mutant).
std::vector<std::string> with_structural_mutants(const std::vector<std::string>& corpus, std::uint64_t seed) {
  fuzz::Rng rng(seed);
  std::vector<std::string> out = corpus;
  for (int k = 0; k < 64; ++k) out.push_back(mutate_structure(corpus[rng.below(corpus.size())], rng));
  return out;
}

}  // namespace

TEST(ReaderFuzz, model_json_inputs_are_loaded_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("model_json");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  fs::copy_file(kSample / "satellite.obj", d / "sample.obj");
  json sample = json::parse(fuzz::read_bytes(kSample / "model.json"));
  sample["mesh"] = "sample.obj";
  const std::vector<std::string> corpus = {fuzz::read_bytes(kData / "example_model.json"), sample.dump(1)};
  for (const std::string& failure : fuzz::corpus_failures(corpus, d, "fuzz.json", [](const fs::path& p, int) {
         return model_problem(load_model(p, ModelLoadOptions{}));
       }))
    ADD_FAILURE() << failure;
  fuzz::Rng structure(0x15);
  const fuzz::FuzzRun run = fuzz::fuzz_reader(
      with_structural_mutants(corpus, 0x150), d, "fuzz.json", kIterations, 0x150, [&](const fs::path& path, int it) {
        // Odd iterations: a fresh structural mutant of a corpus file, as it is.
        if (it % 2) fuzz::write_bytes(path, mutate_structure(corpus[structure.below(corpus.size())], structure));
        ModelLoadOptions options;
        options.allow_unknown_keys = it % 4 == 1;
        return model_problem(load_model(path, options));
      });
  EXPECT_TRUE(run.failures.empty()) << fuzz::report(run);
  EXPECT_GT(run.parsed, 0) << fuzz::report(run);
  EXPECT_GT(run.refused, 0) << fuzz::report(run);
  std::printf("%s\n", fuzz::report(run).c_str());
}

TEST(ReaderFuzz, load_case_inputs_are_read_or_refused_with_a_thermodec_error) {
  const fs::path d = fuzz::work_dir("load_case");
  const ThermalModel base = load_model(kSample / "model.json");
  std::vector<std::string> corpus;
  for (const char* name : {"december.json", "sun_pointing.json"}) corpus.push_back(fuzz::read_bytes(kSample / "cases" / name));
  corpus.push_back(R"({"name": "fixed", "environment": {"type": "fixed_sun", "sun_direction": [0, 1, 0], "solar_flux": 1300},
                       "analysis": {"type": "steady"}})");
  corpus.push_back(R"({"analysis": {"type": "transient_orbit", "steps_per_orbit": 36, "orbits": 2, "time_tolerance_K": 0.1}})");
  fuzz::Rng structure(0xca5e);
  const fuzz::FuzzRun run = fuzz::fuzz_reader(
      with_structural_mutants(corpus, 0xca5), d, "case.json", kIterations, 0xca5, [&](const fs::path& path, int it) {
        if (it % 2) fuzz::write_bytes(path, mutate_structure(corpus[structure.below(corpus.size())], structure));
        ThermalModel m = with_case(base, load_case(path, base));
        return model_problem(m);
      });
  EXPECT_TRUE(run.failures.empty()) << fuzz::report(run);
  EXPECT_GT(run.parsed, 0) << fuzz::report(run);
  EXPECT_GT(run.refused, 0) << fuzz::report(run);
  std::printf("%s\n", fuzz::report(run).c_str());
}
