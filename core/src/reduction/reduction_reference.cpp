#include "thermodec/reduction/reduction_reference.h"

#include <atomic>
#include <chrono>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <map>
#include <memory>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/environment/external_loads.h"
#include "thermodec/radiation/face_view_factors.h"
#include "thermodec/radiation/radiation_reference.h"
#include "thermodec/rays/ray_scene.h"
#include "thermodec/reduction/record_budget.h"

namespace thermodec {

struct ReductionReference::Impl {
  ThermalModel model;
  ReductionReferenceSettings settings;
  SimulationResult result;
  Eigen::VectorXi faces_per_node;
  std::unique_ptr<RadiationReference> radiation;
  LoadSamples load_samples;  //!< the reference's load sampling, reused by trials
  RecordUse records;
  DecimationOptions::ReflectionData reflection;  //!< the decimator's reflected-sunlight cap data
  mutable std::mutex cache_mutex;
  // A trial's result and the candidate's simulation (nodes x times: small), so that the
  // candidate a strategy returns is rebuilt without simulating it again.
  struct Evaluation {
    TrialResult trial;
    std::shared_ptr<const SimulationResult> result;
  };
  mutable std::map<std::vector<double>, Evaluation> cache;
  // Fully verified candidates, so that a later candidate(ratios, true) does not simulate them
  // a second time.
  mutable std::map<std::vector<double>, std::shared_ptr<const Candidate>> verified;
  // Trials by candidate mesh: other ratios often give the same mesh (a node at the end of its
  // decimator's reach, a push bisected between two ratios it reaches alike), and the same
  // mesh gives the same trial.
  mutable std::map<std::uint64_t, Evaluation> by_mesh;
  mutable std::atomic<int> evaluated{0};
  // rebase(): a candidate's own reusable state, and its ratios; trials nearer to it than to
  // the original re-trace what differs from it.
  std::unique_ptr<ReductionReference> base;
  Eigen::VectorXd base_ratios;
};

// The decimator's reflected-sunlight data (DecimationOptions::reflection): per face side, what
// it reflects per unit area, orbit mean over the load positions (the columns after them are
// eclipse edges), (1 - alpha) incident / area [W/m^2], and the nodes its rays first hit; per
// node, its orbit-mean absorbed external power [W].
static DecimationOptions::ReflectionData reflection_data(const ThermalModel& model, const FaceViewFactors& vf,
                                                  const Loads& loads, const Eigen::MatrixXd& incident_W) {
  DecimationOptions::ReflectionData r;
  const SurfaceSides& sides = vf.sides;
  const Eigen::Index steps = loads.reflected_solar_W.cols();
  const int nf = model.mesh.num_faces(), nodes = static_cast<int>(model.nodes.size());
  if (steps == 0 || incident_W.rows() != sides.size() || vf.F.rows() != sides.size()) return r;
  const Eigen::VectorXd alpha = side_absorptivity(model, sides);
  r.flux_W_per_m2.assign(2 * static_cast<size_t>(nf), 0.0);
  std::vector<std::vector<std::pair<int, double>>> views(2 * static_cast<size_t>(nf));
  std::vector<double> by_node(nodes, 0.0);
  for (int s = 0; s < sides.size(); ++s) {
    const size_t slot = 2 * static_cast<size_t>(sides.face[s]) + (sides.is_back[s] ? 1 : 0);
    if (sides.area_m2[s] > 0)
      r.flux_W_per_m2[slot] = (1.0 - alpha[s]) * incident_W.row(s).head(steps).mean() / sides.area_m2[s];
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(vf.F, s); it; ++it)
      if (sides.node[it.col()] >= 0) by_node[sides.node[it.col()]] += it.value();
    for (int g = 0; g < nodes; ++g)
      if (by_node[g] > 0) views[slot].emplace_back(g, by_node[g]), by_node[g] = 0.0;
  }
  r.view_start.push_back(0);
  for (const auto& v : views) {
    for (const auto& [g, f] : v) r.view_node.push_back(g), r.view_fraction.push_back(f);
    r.view_start.push_back(static_cast<int>(r.view_node.size()));
  }
  const Eigen::MatrixXd total = loads.total_W();
  r.node_absorbed_W.resize(nodes);
  for (int g = 0; g < nodes; ++g) r.node_absorbed_W[g] = total.row(g).mean();
  return r;
}

TrialResult trial_result(const SimulationResult& reference, const SimulationResult& candidate,
                         const DecimationResult& decimation) {
  if (reference.temperature_K.rows() != candidate.temperature_K.rows() ||
      reference.temperature_K.cols() != candidate.temperature_K.cols())
    throw InvalidInput("candidate and reference results differ in size");
  TrialResult t;
  t.dT_K = candidate.temperature_K - reference.temperature_K;
  const Eigen::MatrixXd dT = t.dT_K.cwiseAbs();
  t.node_max_abs_dT_K = dT.rowwise().maxCoeff();
  // note: NaN temperatures must not hide behind maxCoeff(): they fail every tolerance.
  t.max_abs_dT_K = dT.array().isNaN().any() ? std::numeric_limits<double>::quiet_NaN()
                                            : (dT.size() ? dT.maxCoeff() : 0.0);
  const int n = static_cast<int>(reference.temperature_K.rows());
  t.node_faces_after = Eigen::VectorXi::Zero(n);
  for (int k = 0; k < n && k < static_cast<int>(decimation.nodes.size()); ++k)
    t.node_faces_after[k] = decimation.nodes[k].faces_after;
  t.faces_after = decimation.mesh.num_faces();
  return t;
}

ReductionReference::ReductionReference(const ThermalModel& model, const ReductionReferenceSettings& settings,
                                       const SimulationResult* reference_result)
    : impl_(std::make_unique<Impl>()) {
  impl_->model = model;
  impl_->settings = settings;
  impl_->settings.simulation.progress = {};  // trials run by the hundred: keep them quiet
  // Trials move single rays' hits: IR rows are counted ray by ray, and so are the full
  // simulations (verify) compared with them.
  impl_->settings.simulation.planar_strata = false;
  const int n = static_cast<int>(model.nodes.size());
  if (n < 1) throw InvalidInput("the model has no thermal nodes");
  impl_->faces_per_node = Eigen::VectorXi::Zero(n);
  for (int f = 0; f < model.mesh.num_faces(); ++f) {
    const int k = model.mesh.face_node[f];
    if (k < 0 || k >= n) throw InvalidInput("face " + std::to_string(f) + " has no thermal node");
    ++impl_->faces_per_node[k];
  }
  for (int k = 0; k < n; ++k)
    if (impl_->faces_per_node[k] == 0)
      throw InvalidInput("node '" + model.nodes[k].name + "' has no faces in the mesh");
  const RecordBudget budget = split_record_budget(record_budget_bytes(settings.record_budget_bytes));
  impl_->settings.simulation.loads.ray_record_budget_bytes =
      budget.load_bytes(ir_record_bytes_kept(model, model.radiation, budget.ir_max_bytes));
  impl_->settings.simulation.loads.earth_ray_geometry_budget_bytes = budget.earth_geometry_bytes;
  // The reference's loads, recording their samples so that trials re-sample only what a
  // change can reach; with the prepared couplings they make the reference simulation itself:
  // simulate_model's chain with couplings that record their rays. The couplings' tracing and
  // the loads side by side (as in simulate_model), the solar reflections once both are done.
  const RayScene scene(model.mesh);
  const ExternalLoadSettings load_settings = chain_load_settings(model, impl_->settings.simulation);
  Loads loads;
  Eigen::MatrixXd solar_incident_W;
  tbb::parallel_invoke(
      [&] {
        impl_->radiation =
            std::make_unique<RadiationReference>(prepare_radiation(model, model.radiation, budget.ir_max_bytes));
      },
      [&] {
        loads = external_loads(model, scene, surface_sides(model), nullptr, load_settings, {}, &impl_->load_samples,
                               nullptr, &solar_incident_W);
      });
  const FaceViewFactors& vf = impl_->radiation->face_view_factors();
  if (load_settings.solar_reflections)
    add_solar_reflections(loads, model, vf.sides, vf, solar_incident_W, nullptr, &impl_->load_samples);
  impl_->reflection = reflection_data(model, vf, loads, solar_incident_W);
  solar_incident_W.resize(0, 0);
  RecordUse& use = impl_->records;
  use.ir_bytes = impl_->radiation->record_bytes();
  use.ir_needed_bytes = impl_->radiation->record_bytes_needed();
  use.ir_budget_bytes = budget.ir_max_bytes;
  use.load_budget_bytes = impl_->settings.simulation.loads.ray_record_budget_bytes;
  use.loads_kept = impl_->load_samples.per_ray;
  for (const auto& r : impl_->load_samples.sun_records) use.load_bytes += r.bytes();
  use.load_bytes += impl_->load_samples.earth_records.bytes();
  use.view_factor_bytes = static_cast<std::size_t>(vf.F.nonZeros()) * (sizeof(double) + sizeof(int));
  for (const auto& hits : impl_->load_samples.earth) use.earth_hit_bytes += hits.size() * sizeof(hits.front());
  impl_->result = reference_result ? *reference_result
                                   : solve_chain(model, impl_->radiation->couplings(), loads, impl_->settings.simulation);
}

ReductionReference::~ReductionReference() = default;

const ThermalModel& ReductionReference::model() const { return impl_->model; }
const SimulationResult& ReductionReference::result() const { return impl_->result; }
const NodeCouplings& ReductionReference::couplings() const { return impl_->radiation->couplings(); }
const Eigen::VectorXi& ReductionReference::faces_per_node() const { return impl_->faces_per_node; }
const DecimationOptions::ReflectionData& ReductionReference::reflection() const { return impl_->reflection; }
int ReductionReference::trials_evaluated() const { return impl_->evaluated; }
const RecordUse& ReductionReference::record_use() const { return impl_->records; }
const DecimationOptions& ReductionReference::decimation_options() const { return impl_->settings.decimation; }

void ReductionReference::set_decimation_options(const DecimationOptions& options) {
  std::lock_guard<std::mutex> lock(impl_->cache_mutex);
  if (impl_->evaluated > 0 || !impl_->cache.empty() || !impl_->verified.empty())
    throw InvalidInput("set_decimation_options: trials were already evaluated with the previous options");
  impl_->settings.decimation = options;
}

Eigen::VectorXd ReductionReference::max_ratio_per_node() const {
  const int n = static_cast<int>(impl_->model.nodes.size());
  const DecimationResult d = decimate_nodes(impl_->model.mesh, Eigen::VectorXd::Constant(n, 0.999),
                                            impl_->settings.decimation);
  Eigen::VectorXd r(n);
  for (int k = 0; k < n; ++k)
    r[k] = 1.0 - static_cast<double>(d.nodes[k].faces_after) / std::max(1, d.nodes[k].faces_before);
  return r;
}

namespace {
// Simulates `cand` (the reference model with another mesh or other sampling salts): fully
// (simulate_model), or reusing the reference's rays and load samples: the IR couplings reuse
// the reference's rays and the loads are sampled with the chain's settings and per-side seeds
// (chain_load_settings), so unchanged faces see unchanged rays, then solved by solve_chain.
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

SimulationResult simulate_candidate(const ThermalModel& cand, const RadiationReference& radiation,
                                    const LoadSamples& load_samples, const ModelSimulationSettings& settings, bool full,
                                    TrialResult::Timing* timing = nullptr, double* redone_fraction = nullptr) {
  TrialResult::Timing ignored;
  TrialResult::Timing& t = timing ? *timing : ignored;
  auto t0 = Clock::now();
  if (full) {
    SimulationResult r = simulate_model(cand, settings);
    t.simulation_s = since(t0);
    return r;
  }
  // Couplings and loads side by side: each alone leaves a core idle at times (the loads' many
  // small per-step passes); together they took 15 % less wall time on the sample's trials.
  // The loads need the couplings' view factors only for the solar reflections, added after.
  const RayScene scene(cand.mesh);  // (traced by both the couplings and the loads)
  const GeometryChange change = geometry_change(radiation, cand);
  const RayScene changed_faces(change.faces);
  LoadReuse reuse;
  reuse.reference = &load_samples;
  reuse.changed_region = change.box;
  reuse.changed_faces = &changed_faces;
  LoadReuse* reusing = change.box.isEmpty() ? nullptr : &reuse;
  const ExternalLoadSettings load_settings = chain_load_settings(cand, settings);
  FaceViewFactors vf;
  NodeCouplings couplings;
  Loads loads;
  Eigen::MatrixXd solar_incident_W;
  tbb::parallel_invoke(
      [&] {
        const auto c0 = Clock::now();
        IncrementalStats stats;
        couplings = radiative_couplings_incremental(radiation, cand, &stats, &vf, &scene);
        // The work redone: rays traced again, or sides whose view-factor rows were rebuilt (each
        // re-reads its rays' records): the larger share (tdrs' returned candidate: 32 % of the
        // rays, all but 12 of 18 237 rows, 22 s of couplings where a full recompute takes 24 s).
        const int sides = stats.reused_sides + stats.changed_sides;
        if (redone_fraction && stats.rays_total > 0 && sides > 0)
          *redone_fraction = std::min(1.0, std::max(double(stats.rays_retraced) / double(stats.rays_total),
                                                    1.0 - double(stats.rows_kept) / sides));
        t.couplings_s = since(c0);
      },
      [&] {
        const auto l0 = Clock::now();
        loads = external_loads(cand, scene, surface_sides(cand), nullptr, load_settings, {}, nullptr, reusing,
                               &solar_incident_W);
        t.loads_s = since(l0);
      });
  if (load_settings.solar_reflections) {
    const auto r0 = Clock::now();
    add_solar_reflections(loads, cand, vf.sides, vf, solar_incident_W, reusing ? &load_samples : nullptr);
    t.loads_s += since(r0);
  }
  t0 = Clock::now();
  SimulationResult r = solve_chain(cand, couplings, loads, settings);
  t.solve_s = since(t0);
  return r;
}

// FNV-1a over everything a trial's result depends on in the candidate mesh (the rest of the
// model is the reference's): a 64-bit identity, like the sampling seeds' hashes.
template <class Derived>
std::uint64_t hash_bytes(std::uint64_t h, const Eigen::DenseBase<Derived>& a) {
  const auto* p = reinterpret_cast<const unsigned char*>(a.derived().data());
  for (std::size_t i = 0; i < sizeof(typename Derived::Scalar) * static_cast<std::size_t>(a.size()); ++i)
    h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}
std::uint64_t mesh_key(const Mesh& m) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  h = hash_bytes(h, Eigen::Vector2i(static_cast<int>(m.V.rows()), static_cast<int>(m.F.rows())));
  h = hash_bytes(h, m.V);
  h = hash_bytes(h, m.F);
  h = hash_bytes(h, m.face_node);
  h = hash_bytes(h, m.face_material);
  return hash_bytes(h, m.face_back_material);
}

// True if `m1` has the faces of `m0`: in the same order, corner for corner at the same
// coordinates, with the same nodes and materials. The vertex numbering may differ: a
// decimation that collapsed nothing still leaves out the vertices no face uses (Juno's
// cleaned mesh keeps some), and every face side, ray and sample of a simulation follows from
// the faces' corners (their side keys and emitters), not from the vertex table.
bool same_surface(const Mesh& m0, const Mesh& m1) {
  if (m1.F.rows() != m0.F.rows() || m1.face_node.size() != m0.face_node.size() ||
      m1.face_material.size() != m0.face_material.size() ||
      m1.face_back_material.size() != m0.face_back_material.size())
    return false;
  if (m1.face_node != m0.face_node || m1.face_material != m0.face_material ||
      m1.face_back_material != m0.face_back_material)
    return false;
  if (m1.V.rows() == m0.V.rows() && m1.V == m0.V && m1.F == m0.F) return true;
  for (Eigen::Index f = 0; f < m0.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (m1.V.row(m1.F(f, k)) != m0.V.row(m0.F(f, k))) return false;
  return true;
}

// The candidate mesh of `ratios` (one per node of `model`) and the seconds it took.
DecimationResult decimate_candidate(const ThermalModel& model, const DecimationOptions& options,
                                    const Eigen::VectorXd& ratios, double& seconds) {
  if (ratios.size() != static_cast<Eigen::Index>(model.nodes.size()))
    throw InvalidInput("one ratio per node expected");
  const auto t0 = Clock::now();
  DecimationResult d = decimate_nodes(model.mesh, ratios, options);
  seconds = since(t0);
  return d;
}
}  // namespace

Candidate ReductionReference::candidate(const Eigen::VectorXd& ratios, bool full) const {
  const Impl& s = *impl_;
  const std::vector<double> key(ratios.data(), ratios.data() + ratios.size());
  std::shared_ptr<const SimulationResult> kept;  // a trial's simulation of these ratios
  {
    std::lock_guard<std::mutex> lock(s.cache_mutex);
    if (full) {
      const auto it = s.verified.find(key);
      if (it != s.verified.end()) return *it->second;
    } else if (const auto it = s.cache.find(key); it != s.cache.end()) {
      kept = it->second.result;
    }
  }
  double seconds = 0.0;
  DecimationResult d = decimate_candidate(s.model, s.settings.decimation, ratios, seconds);
  if (kept) return finish_candidate(std::move(d), *kept, {});
  return candidate_of(std::move(d), seconds, full, nearest(ratios));
}

const ReductionReference& ReductionReference::nearest(const Eigen::VectorXd& ratios) const {
  const Impl& s = *impl_;
  if (!s.base) return *this;
  int from_original = 0, from_base = 0;
  for (Eigen::Index k = 0; k < ratios.size(); ++k) {
    from_original += ratios[k] != 0.0;
    from_base += ratios[k] != s.base_ratios[k];
  }
  return from_base < from_original ? *s.base : *this;
}

Candidate ReductionReference::finish_candidate(DecimationResult decimation, SimulationResult result,
                                               const TrialResult::Timing& timing) const {
  Candidate c;
  c.decimation = std::move(decimation);
  c.model = impl_->model;
  c.model.mesh = c.decimation.mesh;
  c.result = std::move(result);
  c.difference = compare_results(impl_->result, c.result);
  c.trial = trial_result(impl_->result, c.result, c.decimation);
  c.trial.timing = timing;
  return c;
}

Candidate ReductionReference::candidate_of(DecimationResult decimation, double decimation_s, bool full,
                                           const ReductionReference& via) const {
  const Impl& v = *via.impl_;
  ThermalModel cand = impl_->model;
  cand.mesh = decimation.mesh;
  // A decimation that changed nothing against the reused state (a node already at its fewest
  // faces, common on CAD meshes: two-triangle panels) is that state's model itself, face for
  // face and sample for sample: its trial is that model's result, without re-sampling the loads.
  const bool unchanged = !full && same_surface(v.model.mesh, cand.mesh);
  TrialResult::Timing timing;
  timing.decimation_s = decimation_s;
  double redone = unchanged ? 0.0 : 1.0;
  SimulationResult r = unchanged ? v.result
                                 : simulate_candidate(cand, *v.radiation, v.load_samples, impl_->settings.simulation,
                                                      full, &timing, &redone);
  Candidate c = finish_candidate(std::move(decimation), std::move(r), timing);
  c.trial.redone_fraction = redone;
  return c;
}

void ReductionReference::rebase(const Eigen::VectorXd& ratios, std::size_t record_budget_bytes) {
  Impl& s = *impl_;
  double seconds = 0.0;
  const DecimationResult d = decimate_candidate(s.model, s.settings.decimation, ratios, seconds);
  ThermalModel cand = s.model;
  cand.mesh = d.mesh;
  ReductionReferenceSettings settings = s.settings;
  settings.record_budget_bytes = record_budget_bytes;
  {
    std::lock_guard<std::mutex> lock(s.cache_mutex);
    s.base.reset();  // (an earlier rebased state's records go before the new one's are made)
  }
  auto base = std::make_unique<ReductionReference>(cand, settings);
  std::lock_guard<std::mutex> lock(s.cache_mutex);
  s.base = std::move(base);
  s.base_ratios = ratios;
}

TrialNoiseFloor ReductionReference::trial_noise_floor(std::uint64_t salt) const {
  const Impl& s = *impl_;
  const int n = static_cast<int>(s.model.nodes.size());
  if (salt == 0) throw InvalidInput("trial_noise_floor: the salt must be non-zero");
  TrialNoiseFloor out;
  out.node_max_abs_dT_K = Eigen::VectorXd::Zero(n);
  std::vector<TemperatureDifference> diff(n);
  tbb::parallel_for(0, n, [&](int k) {
    ThermalModel cand = s.model;
    cand.nodes[k].sampling_salt = salt;
    diff[k] = compare_results(s.result, simulate_candidate(cand, *s.radiation, s.load_samples, s.settings.simulation, false));
    out.node_max_abs_dT_K[k] = diff[k].max_abs_K;
  });
  for (int k = 0; k < n; ++k)
    if (diff[k].max_abs_K >= out.worst.max_abs_K) {
      out.worst = diff[k];
      out.worst_resampled_node = k;
    }
  return out;
}

TrialResult ReductionReference::trial(const Eigen::VectorXd& ratios) const {
  std::vector<double> key(ratios.data(), ratios.data() + ratios.size());
  {
    std::lock_guard<std::mutex> lock(impl_->cache_mutex);
    auto it = impl_->cache.find(key);
    if (it != impl_->cache.end()) return it->second.trial;
  }
  double seconds = 0.0;
  DecimationResult d = decimate_candidate(impl_->model, impl_->settings.decimation, ratios, seconds);
  const std::uint64_t mesh = mesh_key(d.mesh);
  {
    std::lock_guard<std::mutex> lock(impl_->cache_mutex);
    auto it = impl_->by_mesh.find(mesh);
    if (it != impl_->by_mesh.end()) {
      impl_->cache.emplace(std::move(key), it->second);
      return it->second.trial;
    }
  }
  Candidate c = candidate_of(std::move(d), seconds, false, nearest(ratios));
  const Impl::Evaluation e{c.trial, std::make_shared<const SimulationResult>(std::move(c.result))};
  ++impl_->evaluated;
  std::lock_guard<std::mutex> lock(impl_->cache_mutex);
  impl_->cache.emplace(std::move(key), e);
  impl_->by_mesh.emplace(mesh, e);
  return e.trial;
}

TrialResult ReductionReference::verify(const Eigen::VectorXd& ratios) const {
  ++impl_->evaluated;
  auto c = std::make_shared<const Candidate>(candidate(ratios, true));
  std::lock_guard<std::mutex> lock(impl_->cache_mutex);
  impl_->verified[std::vector<double>(ratios.data(), ratios.data() + ratios.size())] = c;
  return c->trial;
}

}  // namespace thermodec
