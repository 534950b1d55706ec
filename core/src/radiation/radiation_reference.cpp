// The reference of the reduction driver's trials: a model traced once with every ray's first
// hit kept (prepare_radiation), and what differs between it and a candidate by face identity
// (match_sides, geometry_change). The candidates' couplings are in incremental_couplings.cpp.
#include "thermodec/radiation/radiation_reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "reference_records.h"
#include "thermodec/common/errors.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/rays/tracing.h"
#include "view_factor_rows.h"

namespace thermodec {

RadiationReference::RadiationReference(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RadiationReference::RadiationReference(RadiationReference&&) noexcept = default;
RadiationReference& RadiationReference::operator=(RadiationReference&&) noexcept = default;
RadiationReference::~RadiationReference() = default;
const ThermalModel& RadiationReference::model() const { return impl_->model; }
const RadiationSettings& RadiationReference::settings() const { return impl_->settings; }
const FaceViewFactors& RadiationReference::face_view_factors() const { return impl_->vf; }
const GebhartFactors& RadiationReference::gebhart() const { return impl_->gebhart; }
const NodeCouplings& RadiationReference::couplings() const { return impl_->couplings; }
std::size_t RadiationReference::record_bytes() const {
  return impl_->records.empty() ? 0 : impl_->records.size() * detail::kRecordBytesPerRay;
}
std::size_t RadiationReference::record_bytes_needed() const { return impl_->record_bytes_needed; }

namespace detail {

std::uint32_t oct_encode(const float* d) {
  const float l1 = std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]);
  float u = d[0] / l1, v = d[1] / l1;
  if (d[2] < 0.0f) {
    const float pu = (1.0f - std::abs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    const float pv = (1.0f - std::abs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
    u = pu;
    v = pv;
  }
  auto q = [](float x) { return static_cast<std::uint32_t>(std::lround((std::clamp(x, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
  return q(u) | (q(v) << 16);
}

const std::array<CellCone, kCells>& cell_cones() {
  static const std::array<CellCone, kCells> cones = [] {
    std::array<CellCone, kCells> out;
    auto dir = [](double u, double v) {
      float d[3];
      const auto q = [](double x) { return static_cast<std::uint32_t>(std::lround(std::clamp(x, 0.0, 1.0) * 65535.0)); };
      oct_decode(q(u) | (q(v) << 16), d);
      return Eigen::Vector3f(d[0], d[1], d[2]);
    };
    const double w = 1.0 / kCellsPerAxis;
    for (int cv = 0; cv < kCellsPerAxis; ++cv)
      for (int cu = 0; cu < kCellsPerAxis; ++cu) {
        const double u0 = cu * w, v0 = cv * w;
        Eigen::Vector3f axis = dir(u0 + 0.5 * w, v0 + 0.5 * w);
        float worst = 1.0f;
        constexpr int kSamples = 64;
        for (int k = 0; k <= kSamples; ++k) {
          const double t = double(k) / kSamples;
          for (const auto& [u, v] : {std::pair{u0 + t * w, v0}, std::pair{u0 + t * w, v0 + w}, std::pair{u0, v0 + t * w},
                                     std::pair{u0 + w, v0 + t * w}})
            worst = std::min(worst, axis.dot(dir(u, v)));
        }
        const float radius = std::acos(std::clamp(worst, -1.0f, 1.0f)) * 1.1f + 0.02f;
        const float r = std::min(radius, 3.14159265f);
        out[cu + kCellsPerAxis * cv] = {axis, r, std::cos(r), std::sin(r)};
      }
    return out;
  }();
  return cones;
}

namespace {
void extend_by_face(Eigen::AlignedBox3d& box, const Mesh& mesh, int f) {
  for (int k = 0; k < 3; ++k) box.extend(Eigen::Vector3d(mesh.V.row(mesh.F(f, k))));
}
}  // namespace

Mesh changed_faces(const Mesh& a, const std::vector<char>& in_a, const Mesh& b, const std::vector<char>& in_b) {
  const auto count = [](const std::vector<char>& v) { return static_cast<int>(std::count(v.begin(), v.end(), 1)); };
  const int n = count(in_a) + count(in_b);
  Mesh m;
  m.V.resize(3 * n, 3);
  m.F.resize(n, 3);
  m.face_node = Eigen::VectorXi::Zero(n);
  m.face_material = Eigen::VectorXi::Constant(n, -1);
  m.face_back_material = Eigen::VectorXi::Constant(n, -1);
  int k = 0;
  for (const auto& [mesh, flag] : {std::pair<const Mesh*, const std::vector<char>*>{&a, &in_a}, {&b, &in_b}})
    for (int f = 0; f < mesh->num_faces(); ++f)
      if ((*flag)[f]) {
        for (int j = 0; j < 3; ++j) {
          m.V.row(3 * k + j) = mesh->V.row(mesh->F(f, j));
          m.F(k, j) = 3 * k + j;
        }
        ++k;
      }
  return m;
}

SideMatch match_sides(const RadiationReference::Impl& ref, const ThermalModel& candidate, const SurfaceSides& sides,
                      const Eigen::VectorXi& rays) {
  const int S = sides.size(), Sr = ref.vf.sides.size();
  const Eigen::VectorXi& ref_rays = ref.vf.side_rays;
  SideMatch m;
  m.twin.assign(S, -1);
  m.geo_twin.assign(S, -1);
  m.cand_of_ref.assign(Sr, -1);
  for (int c = 0; c < S; ++c) {
    const auto it = ref.side_of_key.find(sides.key[c]);
    if (it != ref.side_of_key.end() && m.cand_of_ref[it->second] < 0) {
      m.geo_twin[c] = it->second;
      m.cand_of_ref[it->second] = c;
      if (ref_rays[it->second] == rays[c]) m.twin[c] = it->second;
    }
  }
  m.added_face.assign(candidate.mesh.num_faces(), 0);
  m.removed_face.assign(ref.model.mesh.num_faces(), 0);
  for (int c = 0; c < S; ++c) {
    (m.twin[c] < 0 ? m.changed_sides : m.reused_sides) += 1;
    if (m.geo_twin[c] < 0 && !m.added_face[sides.face[c]]) {
      m.added_face[sides.face[c]] = 1;
      extend_by_face(m.changed_box, candidate.mesh, sides.face[c]);
    }
  }
  for (int r = 0; r < Sr; ++r)
    if (m.cand_of_ref[r] < 0) {
      ++m.removed_sides;
      if (!m.removed_face[ref.vf.sides.face[r]]) {
        m.removed_face[ref.vf.sides.face[r]] = 1;
        extend_by_face(m.changed_box, ref.model.mesh, ref.vf.sides.face[r]);
      }
    }
  return m;
}

}  // namespace detail

using namespace detail;

RadiationReference prepare_radiation(const ThermalModel& reference, const RadiationSettings& settings,
                                     std::size_t max_record_bytes) {
  auto impl = std::make_unique<RadiationReference::Impl>(reference, settings);
  const int N = static_cast<int>(reference.nodes.size());
  const SurfaceSides sides = surface_sides(impl->model);
  const Eigen::VectorXi rays = side_ray_counts(sides, settings);
  impl->record_bytes_needed = static_cast<std::size_t>(rays.cast<double>().sum()) * kRecordBytesPerRay;
  const bool keep = impl->record_bytes_needed <= max_record_bytes;
  impl->vf = detail::trace_all(impl->scene, sides, settings, keep ? &impl->records : nullptr, &impl->record_begin);
  if (keep) {
    // Directions, compressed, so that a candidate can skip most rays without generating them.
    impl->record_dir.resize(impl->records.size());
    impl->record_origin.resize(impl->records.size());
    const auto sobol_table = tracing::shared_sobol_table(sides.size() ? rays.maxCoeff() : 0);
    const tracing::SobolTable& sobol = *sobol_table;
    tbb::parallel_for(tbb::blocked_range<int>(0, sides.size(), 8), [&](const tbb::blocked_range<int>& range) {
      for (int s = range.begin(); s != range.end(); ++s) {
        const sampling::Emitter e = tracing::side_emitter(impl->model.mesh, sides, s, settings.seed);
        std::uint32_t* out = impl->record_dir.data() + impl->record_begin[s];
        std::uint32_t* out_origin = impl->record_origin.data() + impl->record_begin[s];
        for (int i = 0; i < rays[s]; ++i) {
          float org[3], dir[3], w1, w2;
          sampling::emit(e, sobol[i], true, org, dir);
          sampling::origin_weights(e, sobol[i], w1, w2);
          out[i] = oct_encode(dir);
          out_origin[i] = origin_encode(w1, w2);
        }
      }
    });
    const int S = sides.size();
    impl->ray_order.resize(impl->records.size());
    impl->cell_begin.assign(std::size_t(S) * (kCells + 1), 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, S, 8), [&](const tbb::blocked_range<int>& range) {
      std::vector<int> count(kCells);
      std::vector<tracing::RayRecord> rec;
      std::vector<std::uint32_t> dir;
      for (int s = range.begin(); s != range.end(); ++s) {
        const std::int64_t b = impl->record_begin[s];
        std::fill(count.begin(), count.end(), 0);
        for (int i = 0; i < rays[s]; ++i) ++count[oct_cell(impl->record_dir[b + i])];
        std::int32_t* cb = impl->cell_begin.data() + std::size_t(s) * (kCells + 1);
        for (int c = 0; c < kCells; ++c) cb[c + 1] = cb[c] + count[c];
        std::fill(count.begin(), count.end(), 0);
        for (int i = 0; i < rays[s]; ++i) {
          const int c = oct_cell(impl->record_dir[b + i]);
          impl->ray_order[b + cb[c] + count[c]++] = static_cast<std::uint32_t>(i);
        }
        // Records and directions from ray order into cell order.
        rec.assign(impl->records.begin() + b, impl->records.begin() + b + rays[s]);
        dir.assign(impl->record_dir.begin() + b, impl->record_dir.begin() + b + rays[s]);
        for (int k = 0; k < rays[s]; ++k) {
          impl->records[b + k] = rec[impl->ray_order[b + k]];
          impl->record_dir[b + k] = dir[impl->ray_order[b + k]];
        }
        dir.assign(impl->record_origin.begin() + b, impl->record_origin.begin() + b + rays[s]);
        for (int k = 0; k < rays[s]; ++k) impl->record_origin[b + k] = dir[impl->ray_order[b + k]];
      }
    });
  }
  const Eigen::VectorXd eps = side_emissivity(impl->model, sides);
  impl->gebhart = gebhart_factors(impl->vf, eps, node_groups(sides, N), N + 1);
  impl->couplings = aggregate_couplings(impl->vf, eps, impl->gebhart, N);
  impl->couplings.diagnostics.untraceable_faces = impl->scene.num_skipped_faces();
  for (int s = 0; s < sides.size(); ++s) impl->side_of_key.emplace(sides.key[s], s);
  impl->prims = tracing::prim_table(impl->scene.impl(), sides);
  impl->coincident_side = tracing::coincident_side_flags(impl->prims, sides.size());
  return RadiationReference(std::move(impl));
}

std::size_t ir_record_bytes_kept(const ThermalModel& reference, const RadiationSettings& settings,
                                 std::size_t max_record_bytes) {
  const Eigen::VectorXi rays = side_ray_counts(surface_sides(reference), settings);
  const std::size_t needed = static_cast<std::size_t>(rays.cast<double>().sum()) * kRecordBytesPerRay;
  return needed <= max_record_bytes ? needed : 0;  // (as prepare_radiation decides)
}

GeometryChange geometry_change(const RadiationReference& reference, const ThermalModel& candidate) {
  const RadiationReference::Impl& ref = reference.impl();
  const SurfaceSides sides = surface_sides(candidate);
  const SideMatch m = match_sides(ref, candidate, sides, side_ray_counts(sides, ref.settings));
  GeometryChange change;
  change.box = m.changed_box;
  change.faces = changed_faces(ref.model.mesh, m.removed_face, candidate.mesh, m.added_face);
  return change;
}

}  // namespace thermodec
