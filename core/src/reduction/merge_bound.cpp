// Lower bounds on node merging from the reference temperatures (reduction/merge_bound.h).
#include "thermodec/reduction/merge_bound.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace thermodec {
namespace {

// A set of nodes as 64-bit words.
using Bits = std::vector<std::uint64_t>;

bool has(const Bits& b, int i) { return (b[i >> 6] >> (i & 63)) & 1u; }
void set(Bits& b, int i) { b[i >> 6] |= std::uint64_t(1) << (i & 63); }
void unset(Bits& b, int i) { b[i >> 6] &= ~(std::uint64_t(1) << (i & 63)); }
int count(const Bits& b) {
  int c = 0;
  for (std::uint64_t w : b) c += __builtin_popcountll(w);
  return c;
}
Bits both(const Bits& a, const Bits& b) {
  Bits r(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) r[k] = a[k] & b[k];
  return r;
}
template <class F> void each(const Bits& b, F&& f) {
  for (std::size_t k = 0; k < b.size(); ++k)
    for (std::uint64_t w = b[k]; w; w &= w - 1) f(static_cast<int>(k * 64 + __builtin_ctzll(w)));
}

// Bron-Kerbosch with pivoting (the pivot of P u X with most neighbours in P), keeping the
// largest clique; stops descending after `calls_left` calls.
struct MaxClique {
  const std::vector<Bits>& adjacent;
  long calls_left;
  std::vector<int> current, best;

  void grow(Bits P, Bits X) {
    if (--calls_left < 0) return;
    if (count(P) == 0) {
      if (count(X) == 0 && current.size() > best.size()) best = current;
      return;
    }
    if (current.size() + count(P) <= best.size()) return;  // cannot beat the best
    int pivot = -1, most = -1;
    Bits PX(P.size());
    for (std::size_t k = 0; k < P.size(); ++k) PX[k] = P[k] | X[k];
    each(PX, [&](int u) {
      const int c = count(both(P, adjacent[u]));
      if (c > most) most = c, pivot = u;
    });
    Bits candidates(P.size());
    for (std::size_t k = 0; k < P.size(); ++k) candidates[k] = P[k] & ~adjacent[pivot][k];
    each(candidates, [&](int v) {
      current.push_back(v);
      grow(both(P, adjacent[v]), both(X, adjacent[v]));
      current.pop_back();
      unset(P, v);
      set(X, v);
    });
  }
};

}  // namespace

Eigen::MatrixXd pairwise_spread_K(const std::vector<Eigen::MatrixXd>& temperature_K, const std::vector<int>& never_merged) {
  const Eigen::Index n = temperature_K.empty() ? 0 : temperature_K.front().rows();
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(n, n);
  for (const Eigen::MatrixXd& t : temperature_K)
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = i + 1; j < n; ++j) {
        const double d = (t.row(i) - t.row(j)).cwiseAbs().maxCoeff();
        spread(i, j) = spread(j, i) = std::max(spread(i, j), d);
      }
  const double inf = std::numeric_limits<double>::infinity();
  for (int k : never_merged) {
    spread.row(k).setConstant(inf);
    spread.col(k).setConstant(inf);
    spread(k, k) = 0.0;
  }
  return spread;
}

std::vector<int> nodes_pairwise_apart(const Eigen::MatrixXd& spread_K, double max_dT_K, long max_calls) {
  const int n = static_cast<int>(spread_K.rows());
  const std::size_t words = (static_cast<std::size_t>(n) + 63) / 64;
  std::vector<Bits> apart(n, Bits(words, 0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && spread_K(i, j) > 2.0 * max_dT_K) set(apart[i], j);
  MaxClique search{apart, max_calls, {}, {}};
  Bits all(words, 0);
  for (int i = 0; i < n; ++i) set(all, i);
  search.grow(all, Bits(words, 0));
  if (search.best.empty() && n > 0) search.best = {0};
  std::sort(search.best.begin(), search.best.end());
  return search.best;
}

double least_merge_dT_K(const Eigen::MatrixXd& spread_K, int nodes) {
  const int n = static_cast<int>(spread_K.rows());
  if (nodes >= n) return 0.0;
  // The bound changes only at half of a pairwise spread: bisect over their sorted values.
  std::vector<double> halves{0.0};
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (std::isfinite(spread_K(i, j))) halves.push_back(0.5 * spread_K(i, j));
  std::sort(halves.begin(), halves.end());
  halves.erase(std::unique(halves.begin(), halves.end()), halves.end());
  std::size_t lo = 0, hi = halves.size() - 1;
  if (static_cast<int>(nodes_pairwise_apart(spread_K, halves[hi]).size()) > nodes)
    return std::numeric_limits<double>::infinity();  // never-merged nodes alone exceed `nodes`
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (static_cast<int>(nodes_pairwise_apart(spread_K, halves[mid]).size()) <= nodes) hi = mid;
    else lo = mid + 1;
  }
  return halves[lo];
}

}  // namespace thermodec
