#pragma once
//! Low-discrepancy sampling of rays leaving a triangle, shared by the view factors (radiation/)
//! and the orbit loads (environment/). Inline: it runs once per ray in the hot loops.
//
// Points are the first R points of the 4-D Sobol sequence (Joe & Kuo 2008 direction numbers,
// dimensions 1-4), Owen-scrambled per dimension with the hash-based nested uniform scramble
// of Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020. Each surface side gets
// its own scramble seeds, derived from a hash of its geometry, so that (1) sides are
// independent randomised-QMC estimates (standard errors add), (2) an unchanged face draws the
// same rays in a modified model (correlated sampling), and (3) results do not depend on face
// order or thread count.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace thermodec::sampling {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

inline std::uint64_t hash_combine(std::uint64_t h, std::uint64_t v) { return splitmix64(h ^ splitmix64(v)); }

inline std::uint64_t hash_double(std::uint64_t h, double x) {
  if (x == 0.0) x = 0.0;  // -0 and +0 are the same coordinate
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return hash_combine(h, bits);
}

inline std::uint32_t reverse_bits(std::uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

// Laine-Karras style permutation (Burley 2020, listing 3): a hash that only propagates
// information from lower to higher bits, i.e. a random nested permutation of the bit-reversed
// value.
inline std::uint32_t laine_karras(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

inline std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(laine_karras(reverse_bits(x), seed));
}

inline float to_unit_float(std::uint32_t x) { return float(x >> 8) * (1.0f / 16777216.0f); }

//! Unscrambled 4-D Sobol points 0..n-1 (row-major n x 4).
inline std::vector<std::array<std::uint32_t, 4>> sobol_4d(int n) {
  // Joe-Kuo new-joe-kuo-6.21201, dimensions 2..4 (s, a, m_1..m_s); dimension 1 is van der Corput.
  struct Dim { int s; unsigned a; unsigned m[3]; };
  const Dim dims[3] = {{1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}};
  std::uint32_t V[4][32];
  for (int k = 0; k < 32; ++k) V[0][k] = 1u << (31 - k);
  for (int d = 0; d < 3; ++d) {
    const Dim& D = dims[d];
    std::uint32_t m[33];
    for (int k = 1; k <= D.s; ++k) m[k] = D.m[k - 1];
    for (int k = D.s + 1; k <= 32; ++k) {
      std::uint32_t v = m[k - D.s] ^ (m[k - D.s] << D.s);
      for (int j = 1; j < D.s; ++j)
        if ((D.a >> (D.s - 1 - j)) & 1u) v ^= m[k - j] << j;
      m[k] = v;
    }
    for (int k = 1; k <= 32; ++k) V[d + 1][k - 1] = m[k] << (32 - k);
  }
  std::vector<std::array<std::uint32_t, 4>> pts(n);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 4; ++d) {
      std::uint32_t x = 0;
      for (std::uint32_t idx = std::uint32_t(i), b = 0; idx; idx >>= 1, ++b)
        if (idx & 1u) x ^= V[d][b];
      pts[i][d] = x;
    }
  return pts;
}

//! The same points with every coordinate bit-reversed: owen_scramble(x, seed) =
//! reverse_bits(laine_karras(xr, seed)) with xr precomputed, one reversal less per value in
//! the hot loop (emit() takes this table).
inline std::vector<std::array<std::uint32_t, 4>> sobol_4d_reversed(int n) {
  auto pts = sobol_4d(n);
  for (auto& p : pts)
    for (auto& x : p) x = reverse_bits(x);
  return pts;
}

//! Orthonormal basis (t, b) with n (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
inline void basis(const Eigen::Vector3d& n, Eigen::Vector3d& t, Eigen::Vector3d& b) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double c = n.x() * n.y() * a;
  t = Eigen::Vector3d(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Eigen::Vector3d(c, sign + n.y() * n.y() * a, -n.y());
}

//! Geometry of an emitting surface side, precomputed once.
struct Emitter {
  Eigen::Vector3d a, e1, e2;  // corner and edges of the triangle [m]
  Eigen::Vector3d n, t, b;    // emitting normal and tangent frame
  double offset = 0.0;        // origin lift along n [m], so rays never hit their own face
  std::uint32_t seed[4] = {0, 0, 0, 0};
  // Single-precision copies for the hot loop (Embree traces in float anyway): the lifted
  // corner and the edges/frame.
  float fa[3], fe1[3], fe2[3], fn[3], ft[3], fb[3];
};

inline Emitter make_emitter(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, bool back,
                            std::uint64_t key) {
  Emitter e;
  e.a = a;
  e.e1 = b - a;
  e.e2 = c - a;
  e.n = e.e1.cross(e.e2).normalized();
  if (back) e.n = -e.n;
  basis(e.n, e.t, e.b);
  // note: the lift depends only on this face (not on the scene extent), so an unchanged face
  // emits bit-identical rays in a modified model. 1e-5 x coordinate magnitude is ~100 float
  // ULPs: far above Embree's float rounding, far below any physical gap.
  const double mag = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff(),
                               e.e1.norm(), e.e2.norm()});
  e.offset = 1e-5 * mag;
  for (int d = 0; d < 4; ++d) e.seed[d] = std::uint32_t(hash_combine(key, 0x5eed0000ull + d) >> 32);
  const Eigen::Vector3d lifted = e.a + e.n * e.offset;
  for (int k = 0; k < 3; ++k) {
    e.fa[k] = float(lifted[k]);
    e.fe1[k] = float(e.e1[k]);
    e.fe2[k] = float(e.e2[k]);
    e.fn[k] = float(e.n[k]);
    e.ft[k] = float(e.t[k]);
    e.fb[k] = float(e.b[k]);
  }
  return e;
}

//! Barycentric weights (w1, w2) of edges e1, e2 of ray i's origin: the area-preserving square
//! -> triangle map (Shirley) of its first two coordinates (low distortion keeps the
//! stratification).
inline void origin_weights(const Emitter& e, const std::array<std::uint32_t, 4>& reversed, float& w1, float& w2) {
  const float u1 = to_unit_float(reverse_bits(laine_karras(reversed[0], e.seed[0])));
  const float u2 = to_unit_float(reverse_bits(laine_karras(reversed[1], e.seed[1])));
  const float su = std::sqrt(u1);
  w1 = su * (1.0f - u2);
  w2 = su * u2;
}

//! Ray i of an emitter: origin uniform on the triangle, direction cosine-weighted (Malley) or
//! uniform on the hemisphere. Writes single-precision origin and unit direction.
//! `reversed` is a row of sobol_4d_reversed().
inline void emit(const Emitter& e, const std::array<std::uint32_t, 4>& reversed, bool cosine, float* org, float* dir) {
  float w1, w2;
  origin_weights(e, reversed, w1, w2);
  // note: float is enough: the lift (1e-5 x coordinate magnitude) is ~100x the rounding.
  for (int k = 0; k < 3; ++k) org[k] = e.fa[k] + e.fe1[k] * w1 + e.fe2[k] * w2;
  const float u3 = to_unit_float(reverse_bits(laine_karras(reversed[2], e.seed[2])));
  const float u4 = to_unit_float(reverse_bits(laine_karras(reversed[3], e.seed[3])));
  float ct, st;
  if (cosine) {
    st = std::sqrt(u3);
    ct = std::sqrt(std::max(0.0f, 1.0f - u3));
  } else {
    ct = 1.0f - u3;
    st = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
  }
  float sp, cp;
  ::sincosf(float(2.0 * M_PI) * u4, &sp, &cp);
  const float x = st * cp, y = st * sp;
  for (int k = 0; k < 3; ++k) dir[k] = e.ft[k] * x + e.fb[k] * y + e.fn[k] * ct;
}

}  // namespace thermodec::sampling
