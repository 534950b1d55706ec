#include "model_json.h"

#include <cstdint>
#include <fstream>
#include <set>

namespace thermodec::model_json {
namespace fs = std::filesystem;

std::string lower_extension(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Edit distance with a single row; case-insensitive, so "Solar_Flux" suggests "solar_flux".
std::string Keys::nearest(const std::string& name, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const auto& k : known) {
    std::vector<std::size_t> row(k.size() + 1);
    for (std::size_t j = 0; j <= k.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= name.size(); ++i) {
      std::size_t diag = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= k.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(static_cast<unsigned char>(name[i - 1])) !=
                                                                std::tolower(static_cast<unsigned char>(k[j - 1])))});
        diag = up;
      }
    }
    if (row[k.size()] < best_d) best_d = row[k.size()], best = k;
  }
  return best;
}

// Model and case files are small; a bigger file is a mistake (or /dev/zero), not a model.
constexpr std::uintmax_t kMaxJsonFileBytes = std::uintmax_t{64} << 20;
// No model key nests deeper than 4; the limit keeps recursive code (dump() in messages,
// destruction) far from the stack's end on a file of thousands of '['.
constexpr int kMaxJsonDepth = 32;

json read_json(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw IOError(path.string() + ": not a regular file (a folder, device or FIFO)");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxJsonFileBytes)
    throw IOError(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                  std::to_string(kMaxJsonFileBytes) + "-byte limit for JSON files");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError(path.string() + ": cannot open for reading");
  std::stringstream s;
  s << in.rdbuf();
  // nlohmann keeps the last of two equal keys; a duplicated node or material would silently
  // lose its first definition, so duplicates are refused while parsing (one key set per open
  // object), as is nesting beyond kMaxJsonDepth.
  std::vector<std::set<std::string>> open_objects;
  const auto check = [&](int depth, json::parse_event_t event, json& parsed) {
    if (depth > kMaxJsonDepth)
      throw InvalidInput(path.string() + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    if (event == json::parse_event_t::object_start) open_objects.emplace_back();
    else if (event == json::parse_event_t::object_end && !open_objects.empty()) open_objects.pop_back();
    else if (event == json::parse_event_t::key && !open_objects.empty() &&
             !open_objects.back().insert(parsed.get<std::string>()).second)
      throw InvalidInput(path.string() + ": key '" + parsed.get<std::string>() + "' appears twice in the same object");
    return true;
  };
  try {
    return json::parse(s.str(), check);
  } catch (const json::parse_error& e) {
    // nlohmann's message carries the line and column.
    std::string what = e.what();
    const std::string prefix = "[json.exception.parse_error.101] ";
    if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
    throw InvalidInput(path.string() + ": invalid JSON: " + what);
  } catch (const json::exception& e) {
    throw InvalidInput(path.string() + ": invalid JSON: " + e.what());  // e.g. a number overflowing double
  }
}

}  // namespace thermodec::model_json
