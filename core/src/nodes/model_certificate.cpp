#include "thermodec/nodes/model_certificate.h"

#include <openssl/evp.h>

#include <cstdio>
#include <fstream>
#include <memory>

#include "thermodec/common/errors.h"

namespace thermodec {

std::vector<std::string> certificate_lines(const ModelCertificate& c) {
  std::vector<std::string> out;
  char buf[512];
  out.push_back("reduced model: verified against its original (thermodec reduce)");
  out.push_back("original model: " + c.original_model + " (sha256 " + c.original_sha256 + ")");
  if (!c.original_mesh_sha256.empty()) out.push_back("original mesh sha256: " + c.original_mesh_sha256);
  std::snprintf(buf, sizeof buf, "faces: %d -> %d; tolerance: %.4g K", c.faces_before, c.faces_after, c.tolerance_K);
  out.push_back(buf);
  std::string cases;
  for (const auto& name : c.cases) cases += (cases.empty() ? "" : ", ") + name;
  out.push_back("cases: " + (cases.empty() ? std::string("(the model's own)") : cases));
  std::snprintf(buf, sizeof buf, "verified max |dT|: %.4g +- %.2g K (estimate +- standard error); upper bound %.4g K at %.1f %% confidence",
                c.estimate_K, c.standard_error_K, c.upper_bound_K, 100.0 * c.confidence);
  out.push_back(buf);
  std::string seeds;
  for (const auto s : c.seeds) seeds += (seeds.empty() ? "" : " ") + std::to_string(s);
  out.push_back("verification seeds: " + seeds);
  return out;
}

nlohmann::json certificate_json(const ModelCertificate& c) {
  return {{"original_model", c.original_model}, {"original_sha256", c.original_sha256},
          {"original_mesh_sha256", c.original_mesh_sha256}, {"tolerance_K", c.tolerance_K}, {"cases", c.cases},
          {"estimate_K", c.estimate_K}, {"standard_error_K", c.standard_error_K}, {"upper_bound_K", c.upper_bound_K},
          {"confidence", c.confidence}, {"seeds", c.seeds}, {"faces_before", c.faces_before},
          {"faces_after", c.faces_after}};
}

ModelCertificate certificate_from_json(const nlohmann::json& j) {
  ModelCertificate c;
  try {
    if (!j.is_object()) throw InvalidInput("must be an object {...}");
    c.original_model = j.at("original_model").get<std::string>();
    c.original_sha256 = j.at("original_sha256").get<std::string>();
    c.original_mesh_sha256 = j.value("original_mesh_sha256", std::string());
    c.tolerance_K = j.at("tolerance_K").get<double>();
    c.cases = j.value("cases", std::vector<std::string>{});
    c.estimate_K = j.at("estimate_K").get<double>();
    c.standard_error_K = j.at("standard_error_K").get<double>();
    c.upper_bound_K = j.at("upper_bound_K").get<double>();
    c.confidence = j.at("confidence").get<double>();
    c.seeds = j.value("seeds", std::vector<std::uint64_t>{});
    c.faces_before = j.value("faces_before", 0);
    c.faces_after = j.value("faces_after", 0);
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();
    const auto end = what.find("] ");
    if (end != std::string::npos) what = what.substr(end + 2);
    throw InvalidInput(what);
  }
  return c;
}

std::string file_sha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IOError("cannot read " + path + " to hash it");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) throw IOError("SHA-256 unavailable");
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0)
    EVP_DigestUpdate(ctx.get(), chunk, static_cast<std::size_t>(in.gcount()));
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_DigestFinal_ex(ctx.get(), digest, &n);
  std::string hex;
  char two[3];
  for (unsigned int i = 0; i < n; ++i) std::snprintf(two, sizeof two, "%02x", digest[i]), hex += two;
  return hex;
}

}  // namespace thermodec
