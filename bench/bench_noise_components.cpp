// Which load component, and which node's rays, set the seed-to-seed noise floor, over a set
// of seeds. For every seed k of BENCH_SEEDS (default "1-8") it traces the IR view factors and
// the loads, then simulates with one component's seed moved at a time, the others held at the
// first seed: IR couplings (GR from seed k), solar-reflection view factors (the loads'
// reflections from seed k's view factors), sun + Earth samples (loads seed k), and all (what
// `simulate --seed k` computes with the same boosts). Prints, per component, the worst and
// median pair (max |dT| over nodes and times), the worst pair's node and seeds and every
// node's worst pair; then, for the IR couplings' worst pair, the change of its node's
// temperature when one coupling alone takes the other seed's value.
// Options (environment):
//   BENCH_SEEDS="11-18"      the seeds
//   BENCH_BOOST="dish=64/16,..."  Node::sampling_boost per node, IR/loads (the boosts `simulate`
//                            decides: its result's `sampling.sampling_boost`)
//   BENCH_IR_ONLY=1          the IR couplings' floor only (one loads evaluation)
//   BENCH_ATTRIBUTE="dish:5-8"  (with BENCH_IR_ONLY) the attribution for that node and seed pair
//   BENCH_BY_EMITTER=1       the IR floor when only one node's rays change seed (its sides' rows
//                            of F from seed k, every other row from the first seed)
//   BENCH_SPLIT_NODE=dish    the same for that node's front and back sides apart, IR couplings
//                            and solar reflections
//   BENCH_IR_RECIPROCAL=1    IR couplings from side-pair reciprocal view factors (as the solar
//                            band's), to compare
//   BENCH_EXACT_PAIRS="body_my:wing_my,..." those couplings held at the first seed's value (the
//                            rows kept closed through the couplings to space)
//   BENCH_NO_STRATA=1        IR rows counted without planar strata, shadows without their
//                            controls (as a reduction's reference)
//   BENCH_PAIRS="wing_my:boom,dish:space" (with BENCH_ONLY_PAIRS=1: nothing else) both
//                            directions' one-way couplings per seed
// Usage: bench_noise_components [MODEL]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "thermodec/environment/external_loads.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/gebhart_factors.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/radiation/reciprocal_view_factors.h"
#include "thermodec/thermal/simulate.h"

using namespace thermodec;

namespace {
// "a-b,c" lists: "name=value" or "name:name" items separated by commas.
std::vector<std::string> items(const std::string& spec) {
  std::vector<std::string> out;
  for (std::size_t at = 0; at <= spec.size();) {
    const std::size_t end = std::min(spec.find(',', at), spec.size());
    if (end > at) out.push_back(spec.substr(at, end - at));
    at = end + 1;
  }
  return out;
}

void apply_boosts(ThermalModel& model, const std::string& spec) {
  for (const std::string& it : items(spec)) {
    const std::size_t eq = it.find('=');
    for (Node& n : model.nodes)
      if (eq != std::string::npos && n.name == it.substr(0, eq)) {
        const std::string v = it.substr(eq + 1);
        const std::size_t slash = v.find('/');
        n.sampling_boost.ir = std::stod(v.substr(0, slash));
        n.sampling_boost.loads = slash == std::string::npos ? n.sampling_boost.ir : std::stod(v.substr(slash + 1));
      }
  }
}

struct Floor {
  double worst = 0.0, median = 0.0;
  std::string node;
  int a = 0, b = 0;
  std::vector<double> per_node;  // worst pair of each node
};

Floor floor_of(const std::vector<SimulationResult>& r, const std::vector<int>& seeds) {
  Floor f;
  std::vector<double> v;
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = i + 1; j < r.size(); ++j) {
      const TemperatureDifference d = compare_results(r[i], r[j]);
      v.push_back(d.max_abs_K);
      if (d.max_abs_K > f.worst) {
        f.worst = d.max_abs_K;
        f.node = d.node;
        f.a = seeds[i];
        f.b = seeds[j];
      }
      f.per_node.resize(d.per_node.size(), 0.0);
      for (std::size_t n = 0; n < d.per_node.size(); ++n) f.per_node[n] = std::max(f.per_node[n], d.per_node[n].max_abs_K);
    }
  std::sort(v.begin(), v.end());
  if (!v.empty()) f.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return f;
}

void print_floor(const char* what, const Floor& f, const ThermalModel& model) {
  std::printf("  %-30s %.5f K (%s, %d-%d) / %.5f K\n   per node:", what, f.worst, f.node.c_str(), f.a, f.b, f.median);
  for (std::size_t n = 0; n < f.per_node.size(); ++n) std::printf(" %s %.4f", model.nodes[n].name.c_str(), f.per_node[n]);
  std::printf("\n");
}

// Everything traced once per seed.
struct Study {
  ThermalModel model;
  std::vector<int> seeds;
  std::unique_ptr<RayScene> scene;
  SurfaceSides sides;
  Eigen::VectorXd eps;
  int N = 0, K = 0;
  std::vector<FaceViewFactors> vf;
  std::vector<NodeCouplings> nc;
  std::vector<Eigen::MatrixXd> raw;  // N x (N + 2) one-way couplings, row = emitter
  Loads loads0;                      // loads at the first seed

  int node(const std::string& name) const {
    for (int n = 0; n < N; ++n)
      if (model.nodes[n].name == name) return n;
    return name == "space" ? N + 1 : -1;
  }
  NodeCouplings couple(const FaceViewFactors& v) const {
    const GebhartFactors gb = gebhart_factors(v, eps, node_groups(sides, N), N + 1);
    return aggregate_couplings(v, eps, gb, N);
  }
  Loads loads(int seed, const FaceViewFactors& v) const {
    ExternalLoadSettings ls;
    ls.seed = seed;
    ls.planar_shadow_controls = std::getenv("BENCH_NO_STRATA") == nullptr;  // as simulate samples
    return external_loads(model, *scene, sides, &v, ls);
  }
  // The first seed's view factors with the rows of the sides `moves` picks from seed k's.
  FaceViewFactors mixed(int k, const std::function<bool(int)>& moves) const {
    FaceViewFactors m = vf[0];
    std::vector<Eigen::Triplet<double>> trip;
    for (int s = 0; s < sides.size(); ++s) {
      const FaceViewFactors& src = moves(s) ? vf[k] : vf[0];
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(src.F, s); it; ++it)
        trip.emplace_back(s, it.col(), it.value());
      m.to_space[s] = src.to_space[s];
    }
    m.F.setZero();
    m.F.setFromTriplets(trip.begin(), trip.end());
    return m;
  }
};

void trace(Study& st) {
  st.N = static_cast<int>(st.model.nodes.size());
  st.K = static_cast<int>(st.seeds.size());
  st.scene = std::make_unique<RayScene>(st.model.mesh);
  st.sides = surface_sides(st.model);
  st.eps = side_emissivity(st.model, st.sides);
  st.vf.resize(st.K);
  st.nc.resize(st.K);
  st.raw.resize(st.K);
  for (int k = 0; k < st.K; ++k) {
    RadiationSettings rs = st.model.radiation;
    rs.seed = st.seeds[k];
    rs.planar_strata = std::getenv("BENCH_NO_STRATA") == nullptr;  // as simulate traces
    st.vf[k] = face_view_factors(*st.scene, st.sides, rs);
    // BENCH_IR_RECIPROCAL: the IR couplings from side-pair reciprocal view factors.
    const FaceViewFactors ir = std::getenv("BENCH_IR_RECIPROCAL") ? reciprocal_view_factors(st.vf[k]) : st.vf[k];
    const GebhartFactors gb = gebhart_factors(ir, st.eps, node_groups(st.sides, st.N), st.N + 1);
    st.nc[k] = aggregate_couplings(ir, st.eps, gb, st.N);
    st.raw[k] = Eigen::MatrixXd::Zero(st.N, st.N + 2);
    for (int s = 0; s < st.sides.size(); ++s)
      if (st.sides.node[s] >= 0) st.raw[k].row(st.sides.node[s]) += st.sides.area_m2[s] * st.eps[s] * gb.B.row(s);
  }
}

// Those couplings without noise: every seed takes the first seed's value, and each node's
// coupling to space takes the change (its row stays closed).
void hold_exact(Study& st, const std::string& spec) {
  for (const std::string& it : items(spec)) {
    const std::size_t colon = it.find(':');
    const int i = st.node(it.substr(0, colon)), j = st.node(it.substr(colon + 1));
    if (i < 0 || j < 0 || i >= st.N || j >= st.N) continue;
    for (int k = 1; k < st.K; ++k) {
      const double d = st.nc[0].radiative_couplings_m2(i, j) - st.nc[k].radiative_couplings_m2(i, j);
      st.nc[k].radiative_couplings_m2(i, j) = st.nc[k].radiative_couplings_m2(j, i) = st.nc[0].radiative_couplings_m2(i, j);
      st.nc[k].to_space_couplings_m2[i] -= d;
      st.nc[k].to_space_couplings_m2[j] -= d;
    }
  }
}

// Each component's floor; returns the IR couplings' runs (for the attribution).
std::vector<SimulationResult> components(const Study& st, Floor& ir_floor) {
  const int K = st.K;
  std::vector<SimulationResult> r_ir(K), r_refl(K), r_sample(K), r_all(K);
  for (int k = 0; k < K; ++k) {
    const Loads all = k == 0 ? st.loads0 : st.loads(st.seeds[k], st.vf[k]);
    r_ir[k] = simulate(st.model, st.nc[k], st.loads0);
    r_refl[k] = k == 0 ? r_ir[0] : simulate(st.model, st.nc[0], st.loads(st.seeds[0], st.vf[k]));
    r_sample[k] = k == 0 ? r_ir[0] : simulate(st.model, st.nc[0], st.loads(st.seeds[k], st.vf[0]));
    r_all[k] = simulate(st.model, st.nc[k], all);
  }
  std::printf("seeds %d-%d (%d pairs); worst pair (node, seeds) / median pair\n", st.seeds.front(), st.seeds.back(),
              K * (K - 1) / 2);
  ir_floor = floor_of(r_ir, st.seeds);
  print_floor("IR couplings", ir_floor, st.model);
  print_floor("solar-reflection view factors", floor_of(r_refl, st.seeds), st.model);
  print_floor("sun + Earth samples", floor_of(r_sample, st.seeds), st.model);
  print_floor("all", floor_of(r_all, st.seeds), st.model);
  return r_ir;
}

// The IR worst pair: one coupling at a time takes seed b's value in seed a's couplings; prints
// the change of the worst node's temperature.
void attribute(const Study& st, const Floor& f, const std::vector<SimulationResult>& r_ir) {
  const auto at = [&](int seed) { return static_cast<int>(std::find(st.seeds.begin(), st.seeds.end(), seed) - st.seeds.begin()); };
  const int ia = at(f.a), ib = at(f.b), worst = std::max(0, st.node(f.node));
  const NodeCouplings &a = st.nc[ia], &b = st.nc[ib];
  std::printf("IR worst pair %d-%d, node %s: max |dT| with one coupling moved to seed %d\n", f.a, f.b, f.node.c_str(), f.b);
  for (int i = 0; i < st.N; ++i)
    for (int j = -1; j < st.N; ++j) {  // j < 0: to space
      if (j >= 0 && j < i) continue;
      const double g = j < 0 ? a.to_space_couplings_m2[i] : a.radiative_couplings_m2(i, j);
      const double dg = (j < 0 ? b.to_space_couplings_m2[i] : b.radiative_couplings_m2(i, j)) - g;
      if (dg == 0.0) continue;
      NodeCouplings c = a;
      if (j < 0) c.to_space_couplings_m2[i] += dg;
      else c.radiative_couplings_m2(i, j) = c.radiative_couplings_m2(j, i) = g + dg;
      const SimulationResult r = simulate(st.model, c, st.loads0);
      const double dT = (r.temperature_K - r_ir[ia].temperature_K).row(worst).cwiseAbs().maxCoeff();
      if (dT > 2e-5)
        std::printf("  %-11s - %-11s GR %.5f m^2, change %+.2e m^2 (%+.1e of it): %.5f K\n", st.model.nodes[i].name.c_str(),
                    j < 0 ? "space" : st.model.nodes[j].name.c_str(), g, dg, g > 0 ? dg / g : 0.0, dT);
    }
}

// The IR floor (and, with `reflections`, the solar reflections' floor) when only the sides
// `moves` picks change seed.
void moving_sides(const Study& st, const std::string& what, const std::function<bool(int)>& moves, bool reflections) {
  std::vector<SimulationResult> r(st.K), rr(st.K);
  for (int k = 0; k < st.K; ++k) {
    const FaceViewFactors m = st.mixed(k, moves);
    r[k] = simulate(st.model, st.couple(m), st.loads0);
    if (reflections) rr[k] = simulate(st.model, st.nc[0], st.loads(st.seeds[0], m));
  }
  print_floor((what + ", IR").c_str(), floor_of(r, st.seeds), st.model);
  if (reflections) print_floor((what + ", reflections").c_str(), floor_of(rr, st.seeds), st.model);
}

// Per seed, both one-way estimates of the couplings named in spec ("wing_my:boom,dish:space").
void one_way(const Study& st, const std::string& spec) {
  for (const std::string& it : items(spec)) {
    const std::size_t colon = it.find(':');
    const int i = st.node(it.substr(0, colon)), j = st.node(it.substr(colon + 1));
    if (i < 0 || i >= st.N || j < 0) continue;
    const bool space = j > st.N;
    std::printf("%s - %s: seed, GR from %s's rays, from the other's, combined (sigma)\n", st.model.nodes[i].name.c_str(),
                space ? "space" : st.model.nodes[j].name.c_str(), st.model.nodes[i].name.c_str());
    for (int k = 0; k < st.K; ++k) {
      const NodeCouplings& c = st.nc[k];
      std::printf("  %3d  %.6f  %.6f  %.6f (%.1e)\n", st.seeds[k], st.raw[k](i, j), space ? 0.0 : st.raw[k](j, i),
                  space ? c.to_space_couplings_m2[i] : c.radiative_couplings_m2(i, j),
                  space ? c.to_space_couplings_standard_error[i] : c.radiative_couplings_standard_error(i, j));
    }
  }
}
}  // namespace

int main(int argc, char** argv) {
  Study st;
  st.model = load_model(argc > 1 ? argv[1] : std::string(THERMODEC_SOURCE_DIR) + "/sample_models/satellite/model.json");
  if (const char* b = std::getenv("BENCH_BOOST")) apply_boosts(st.model, b);
  const std::string range = std::getenv("BENCH_SEEDS") ? std::getenv("BENCH_SEEDS") : "1-8";
  const std::size_t dash = range.find('-');
  const int lo = std::stoi(range.substr(0, dash)), hi = dash == std::string::npos ? lo : std::stoi(range.substr(dash + 1));
  for (int k = lo; k <= hi; ++k) st.seeds.push_back(k);
  if (st.seeds.size() < 2) {
    std::fprintf(stderr, "BENCH_SEEDS: at least two seeds (e.g. 1-8)\n");
    return 2;
  }
  trace(st);
  if (const char* p = std::getenv("BENCH_EXACT_PAIRS")) hold_exact(st, p);
  if (const char* p = std::getenv("BENCH_PAIRS")) one_way(st, p);
  if (std::getenv("BENCH_ONLY_PAIRS")) return 0;
  st.loads0 = st.loads(st.seeds[0], st.vf[0]);
  if (std::getenv("BENCH_IR_ONLY")) {
    std::vector<SimulationResult> r(st.K);
    for (int k = 0; k < st.K; ++k) r[k] = simulate(st.model, st.nc[k], st.loads0);
    const Floor f = floor_of(r, st.seeds);
    print_floor("IR couplings only", f, st.model);
    if (const char* spec = std::getenv("BENCH_ATTRIBUTE")) {  // "dish:5-8"
      const std::string a = spec;
      const std::size_t colon = a.find(':'), d = a.find('-', colon);
      Floor g = f;
      g.node = a.substr(0, colon);
      g.a = std::stoi(a.substr(colon + 1, d - colon - 1));
      g.b = std::stoi(a.substr(d + 1));
      attribute(st, g, r);
    }
  } else {
    Floor ir;
    const std::vector<SimulationResult> r_ir = components(st, ir);
    attribute(st, ir, r_ir);
  }
  if (std::getenv("BENCH_BY_EMITTER")) {
    std::printf("only one node's rays moving (worst pair, node / median; every node's worst pair):\n");
    for (int x = 0; x < st.N; ++x)
      moving_sides(st, st.model.nodes[x].name, [&](int s) { return st.sides.node[s] == x; }, false);
  }
  if (const char* split = std::getenv("BENCH_SPLIT_NODE")) {
    const int x = st.node(split);
    for (int back = 0; back < 2; ++back)
      moving_sides(st, std::string(split) + (back ? " back" : " front"),
                   [&](int s) { return st.sides.node[s] == x && st.sides.is_back[s] == back; }, true);
  }
  return 0;
}
