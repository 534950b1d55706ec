#pragma once
// Reading the model file and load-case files (docs/model-format.md): JSON read with duplicate
// keys and deep nesting refused, every value checked with the file and the dotted key path
// ("nodes.body_px.capacitance") in the message, and the environment, analysis and radiation
// sections parsed the same way wherever they appear. Private to nodes/.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/common/printable.h"
#include "thermodec/nodes/thermal_model.h"

namespace thermodec::model_json {

using json = nlohmann::ordered_json;

//! The lower-case extension of `p`, with its dot (".json").
std::string lower_extension(const std::filesystem::path& p);

// Error context: the model file and the dotted key path ("nodes.body_px.capacitance").
class Keys {
 public:
  explicit Keys(std::string file, bool allow_unknown = false) : file_(std::move(file)), allow_unknown_(allow_unknown) {}

  //! An unknown key: an error naming the nearest known key, or a warning when allowed.
  void unknown(const std::string& key, const std::string& name, const std::vector<std::string>& known,
               const std::string& context = "") const {
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    const std::string hint = nearest(name, known);
    const std::string what = "unknown key" + context + (hint.empty() ? "" : " (did you mean '" + hint + "'?)") +
                             "; known: " + list;
    if (!allow_unknown_) fail(join(key, name), what + " (--allow-unknown-keys ignores it)");
    std::cerr << "thermodec: warning: " << file_ << ": '" << join(key, name) << "': " << what << "; ignored\n";
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InvalidInput(file_ + ": " + (key.empty() ? std::string() : "'" + key + "': ") + what);
  }

  void require_object(const json& j, const std::string& key) const {
    if (!j.is_object()) fail(key, "must be an object {...}, got " + std::string(j.type_name()));
  }

  void only_keys(const json& obj, const std::string& key, std::initializer_list<const char*> known,
                 const std::string& context = "") const {
    for (const auto& item : obj.items()) {
      if (std::find_if(known.begin(), known.end(), [&](const char* k) { return item.key() == k; }) != known.end()) continue;
      unknown(key, item.key(), std::vector<std::string>(known.begin(), known.end()), context);
    }
  }

  //! The known key closest to `name` by edit distance, if close enough to be a typo.
  static std::string nearest(const std::string& name, const std::vector<std::string>& known);

  double number(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_number()) fail(join(key, name), "must be a number, got " + std::string(v.type_name()));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(join(key, name), "must be finite");
    return x;
  }

  double number_in(const json& obj, const std::string& key, const char* name, double lo, double hi,
                   bool lo_open, const char* unit) const {
    const double x = number(obj, key, name);
    if ((lo_open ? !(x > lo) : !(x >= lo)) || !(x <= hi)) {
      std::ostringstream s;
      s << "must be in " << (lo_open ? "(" : "[") << lo << ", " << hi << "]" << unit << ", got " << x;
      fail(join(key, name), s.str());
    }
    return x;
  }

  long long integer(const json& obj, const std::string& key, const char* name, long long lo, long long hi) const {
    const json& v = obj.at(name);
    long long x = 0;
    if (v.is_number_integer()) {
      if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi))
        fail(join(key, name), "must be at most " + std::to_string(hi));
      x = v.get<long long>();
    } else if (v.is_number_float() && std::isfinite(v.get<double>()) && v.get<double>() == std::floor(v.get<double>()) &&
               std::abs(v.get<double>()) < 9e15) {
      x = static_cast<long long>(v.get<double>());
    } else {
      fail(join(key, name), "must be an integer, got " + v.dump());
    }
    if (x < lo || x > hi) fail(join(key, name), "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
    return x;
  }

  std::string string(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_string() || v.get<std::string>().empty()) fail(join(key, name), "must be a non-empty string");
    return v.get<std::string>();
  }

  bool boolean(const json& obj, const std::string& key, const char* name) const {
    const json& v = obj.at(name);
    if (!v.is_boolean()) fail(join(key, name), "must be true or false");
    return v.get<bool>();
  }

  //! Node and material names end up as whole lines of OBJ and PLY files: one printable line.
  void name(const std::string& key, const std::string& n) const {
    if (has_control_characters(n))
      fail(key, "names must not contain control characters (newline, tab, NUL, escape, direction overrides)");
    if (n.empty() || n.front() == ' ' || n.back() == ' ') fail(key, "names must be non-empty without leading/trailing spaces");
  }

  static std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

 private:
  std::string file_;
  bool allow_unknown_ = false;
};

//! The file parsed as JSON; an unreadable, oversized, duplicated-key or too deeply nested file
//! is an IOError/InvalidInput naming the file (and the line and column of a syntax error).
json read_json(const std::filesystem::path& path);

//! The "environment" section over `env`'s current values (fixed_sun or orbit).
void parse_environment(const json& j, const Keys& k, Environment& env);
//! The "analysis" section over `a`'s current values (steady or transient_orbit).
void parse_analysis(const json& j, const Keys& k, Analysis& a);
//! An orbit transient needs an orbit: refused otherwise, in model files and case files alike.
void check_analysis_fits_environment(const Analysis& a, const Environment& e, const Keys& k);
//! A node's "power_schedule_W": [[t_s, W], ...], t from 0, increasing, finite W.
std::vector<std::pair<double, double>> power_schedule(const json& j, const Keys& k, const std::string& key);
//! A node's "heater": {"on_K", "off_K", "power_W"}, 0 < on_K < off_K, power_W > 0.
Thermostat thermostat(const json& j, const Keys& k, const std::string& key);
//! Heaters need a free node with C > 0 and a transient orbit analysis; schedules an orbit.
void check_internal_power(const ThermalModel& model, const Keys& k);
//! The "radiation" section (rays per face, minimum rays per node, seed).
void parse_radiation(const json& j, const Keys& k, RadiationSettings& r);

}  // namespace thermodec::model_json
