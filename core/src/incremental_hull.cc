#include "incremental_hull.h"

#include <algorithm>
#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "internal_util.h"

namespace ovpc::internal {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Facet = HullWorkspace::Facet;

// Bound on the rounding error of a 3x3 determinant det(u, v, w) of rounded differences, evaluated as
// (u x v) . w in double: |error| <= 8.1 eps * |u|_1 |v|_1 |w|_1 (eps = 2^-53; see docs/PERFORMANCE.md).
// We use more than ten times that. The absolute term covers underflow in tiny products.
constexpr double kErrorFactor = 1e-14;
constexpr double kUnderflowGuard = 1e-290;

double L1(const Vec3& v) { return std::abs(v.x()) + std::abs(v.y()) + std::abs(v.z()); }

int ExactOrientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const CGAL::Orientation o = CGAL::orientation(Point3(a.x(), a.y(), a.z()), Point3(b.x(), b.y(), b.z()),
                                                Point3(c.x(), c.y(), c.z()), Point3(d.x(), d.y(), d.z()));
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

// Sign of det(b - a, c - a, d - a): +1 if d is on the side that (b - a) x (c - a) points to.
int Orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double s = u.cross(v).dot(w);
  const double bound = kErrorFactor * L1(u) * L1(v) * L1(w) + kUnderflowGuard;
  if (s > bound) return 1;
  if (s < -bound) return -1;
  return ExactOrientation(a, b, c, d);
}

// Sign of p above the facet's outward plane, with the facet's cached normal.
int AbovePlane(const Facet& f, const Points& pts, int p) {
  const Vec3& a = pts[f.v[0]];
  const Vec3 w = pts[p] - a;
  const double s = f.normal.dot(w);
  const double bound = f.error_scale * L1(w) + kUnderflowGuard;
  if (s > bound) return 1;
  if (s < -bound) return -1;
  return ExactOrientation(a, pts[f.v[1]], pts[f.v[2]], pts[p]);
}


class Builder {
 public:
  Builder(const Points& pts, HullWorkspace* ws) : pts_(pts), ws_(*ws) {}

  HullStatus Run(std::vector<int>* vertices, std::vector<std::array<int, 3>>* faces) {
    ws_.facets.clear();
    ws_.free_facets.clear();
    const int n = static_cast<int>(pts_.size());
    if (n < 4) return HullStatus::kDegenerate;
    ws_.new_facet_from.assign(n, -1);
    ws_.new_facet_to.assign(n, -1);
    std::array<int, 4> tetra;
    if (!InitialTetrahedron(&tetra)) return HullStatus::kDegenerate;
    BuildInsertionOrder(tetra);
    int last = 0;
    for (int p : ws_.order) {
      if (!Insert(p, &last)) return HullStatus::kDegenerate;
    }
    faces->clear();
    vertices->clear();
    std::vector<int>& is_vertex = ws_.new_facet_from;  // all -1 again here; reused as a flag
    for (const Facet& f : ws_.facets) {
      if (!f.alive) continue;
      faces->push_back(f.v);
      for (int v : f.v) is_vertex[v] = 1;
    }
    for (int i = 0; i < n; ++i) {
      if (is_vertex[i] == 1) vertices->push_back(i);
    }
    return HullStatus::kOk;
  }

 private:
  bool InitialTetrahedron(std::array<int, 4>* tetra) {
    const int n = static_cast<int>(pts_.size());
    // The most distant pair among the axis extremes, then the point farthest from their line, then
    // the point farthest from their plane (floating point picks; exact checks follow).
    std::array<int, 6> ext = {0, 0, 0, 0, 0, 0};
    for (int i = 1; i < n; ++i) {
      for (int k = 0; k < 3; ++k) {
        if (pts_[i][k] < pts_[ext[2 * k]][k]) ext[2 * k] = i;
        if (pts_[i][k] > pts_[ext[2 * k + 1]][k]) ext[2 * k + 1] = i;
      }
    }
    int a = ext[0], b = ext[1];
    double best = -1.0;
    for (int i = 0; i < 6; ++i) {
      for (int j = i + 1; j < 6; ++j) {
        const double d = (pts_[ext[i]] - pts_[ext[j]]).squaredNorm();
        if (d > best) best = d, a = ext[i], b = ext[j];
      }
    }
    const Vec3 ab = pts_[b] - pts_[a];
    int c = -1;
    best = 0.0;
    for (int i = 0; i < n; ++i) {
      const double d = ab.cross(pts_[i] - pts_[a]).squaredNorm();
      if (d > best) best = d, c = i;
    }
    if (c < 0) return false;
    const Vec3 normal = ab.cross(pts_[c] - pts_[a]);
    int d = -1;
    best = 0.0;
    for (int i = 0; i < n; ++i) {
      const double h = std::abs(normal.dot(pts_[i] - pts_[a]));
      if (h > best) best = h, d = i;
    }
    if (d < 0) return false;
    int o = Orientation(pts_[a], pts_[b], pts_[c], pts_[d]);
    if (o == 0) return false;
    if (o > 0) std::swap(b, c);  // now d is below (a, b, c)
    *tetra = {a, b, c, d};
    const int f0 = NewFacet(a, b, c), f1 = NewFacet(a, d, b), f2 = NewFacet(b, d, c), f3 = NewFacet(c, d, a);
    const std::array<int, 4> fs = {f0, f1, f2, f3};
    for (int f : fs) {
      for (int g : fs) {
        if (f != g) LinkIfShared(f, g);
      }
    }
    centre_ = (pts_[a] + pts_[b] + pts_[c] + pts_[d]) / 4.0;
    // The centre must be strictly inside: every later facet then sees it below.
    const std::array<int, 4> opposite = {d, c, a, b};
    for (int k = 0; k < 4; ++k) {
      const Facet& f = ws_.facets[fs[k]];
      if (Orientation(pts_[f.v[0]], pts_[f.v[1]], pts_[f.v[2]], pts_[opposite[k]]) >= 0) return false;
      if (Orientation(pts_[f.v[0]], pts_[f.v[1]], pts_[f.v[2]], centre_) >= 0) return false;
    }
    return true;
  }

  void LinkIfShared(int f, int g) {
    Facet& F = ws_.facets[f];
    const Facet& G = ws_.facets[g];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (F.v[i] == G.v[(j + 1) % 3] && F.v[(i + 1) % 3] == G.v[j]) F.nb[i] = g;
      }
    }
  }

  // Biased randomised insertion order (BRIO): each point gets a pseudo-random round from a hash of
  // its index (round sizes grow four-fold, so most points are in the last round), and points are in
  // Morton (Z-curve) order within a round. Deterministic, O(n) with a radix sort.
  void BuildInsertionOrder(const std::array<int, 4>& tetra) {
    const int n = static_cast<int>(pts_.size());
    Vec3 lo = pts_[0], hi = pts_[0];
    for (const Vec3& p : pts_) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Vec3 scale = (1023.0 / (hi - lo).cwiseMax(Vec3::Constant(1e-300)).array()).matrix();
    int rounds = 1;
    for (int size = 64; size < n; size *= 4) ++rounds;
    auto& keyed = ws_.keyed;
    keyed.clear();
    for (int i = 0; i < n; ++i) {
      if (i == tetra[0] || i == tetra[1] || i == tetra[2] || i == tetra[3]) continue;
      const Vec3 q = (pts_[i] - lo).cwiseProduct(scale);
      const std::uint64_t morton = Spread(static_cast<std::uint32_t>(q.x())) |
                                   (Spread(static_cast<std::uint32_t>(q.y())) << 1) |
                                   (Spread(static_cast<std::uint32_t>(q.z())) << 2);
      const std::uint64_t h = Mix(static_cast<std::uint64_t>(i));
      const int later = h == 0 ? 32 : __builtin_clzll(h) / 2;  // P(later >= k) = 4^-k
      const std::uint64_t round = static_cast<std::uint64_t>(std::max(0, rounds - 1 - later));
      keyed.push_back({(round << 30) | morton, i});
    }
    RadixSort(&keyed, &ws_.keyed_tmp);
    ws_.order.clear();
    for (const auto& k : keyed) ws_.order.push_back(k.second);
  }

  // Spreads the low 10 bits of x so that there are two zero bits between consecutive bits.
  static std::uint64_t Spread(std::uint32_t x) {
    std::uint64_t v = x & 0x3ffu;
    v = (v | (v << 16)) & 0x030000ffULL;
    v = (v | (v << 8)) & 0x0300f00fULL;
    v = (v | (v << 4)) & 0x030c30c3ULL;
    v = (v | (v << 2)) & 0x09249249ULL;
    return v;
  }

  // LSD radix sort on the low 33 bits of the key (3 rounds bits + 30 Morton bits), stable.
  static void RadixSort(std::vector<std::pair<std::uint64_t, int>>* a, std::vector<std::pair<std::uint64_t, int>>* tmp) {
    tmp->resize(a->size());
    for (int shift = 0; shift < 33; shift += 11) {
      std::array<std::size_t, 2049> count{};
      for (const auto& e : *a) ++count[((e.first >> shift) & 2047u) + 1];
      for (int b = 0; b < 2048; ++b) count[b + 1] += count[b];
      for (const auto& e : *a) (*tmp)[count[(e.first >> shift) & 2047u]++] = e;
      a->swap(*tmp);
    }
  }

  int NewFacet(int a, int b, int c) {
    int id;
    if (!ws_.free_facets.empty()) {
      id = ws_.free_facets.back();
      ws_.free_facets.pop_back();
    } else {
      id = static_cast<int>(ws_.facets.size());
      ws_.facets.emplace_back();
    }
    Facet& f = ws_.facets[id];
    f.v = {a, b, c};
    f.nb = {-1, -1, -1};
    const Vec3 u = pts_[b] - pts_[a], v = pts_[c] - pts_[a];
    f.normal = u.cross(v);
    f.error_scale = kErrorFactor * L1(u) * L1(v);
    f.stamp = 0;
    f.above = false;
    f.alive = true;
    ++alive_;
    return id;
  }

  // Walks from `start` to the facet whose cone from the centre contains p's direction.
  // Returns -1 if the walk does not end (which only a bug could cause).
  int Locate(int p, int start) {
    int f = start;
    const int max_steps = 4 * alive_ + 64;
    for (int step = 0; step < max_steps; ++step) {
      const Facet& F = ws_.facets[f];
      const int first = static_cast<int>((static_cast<unsigned>(p) + static_cast<unsigned>(step)) % 3u);
      int next = -1;
      for (int k = 0; k < 3; ++k) {
        const int e = (first + k) % 3;
        if (Orientation(centre_, pts_[F.v[e]], pts_[F.v[(e + 1) % 3]], pts_[p]) < 0) {
          next = F.nb[e];
          break;
        }
      }
      if (next < 0) return f;
      f = next;
    }
    return -1;
  }

  bool Insert(int p, int* last) {
    const int f = Locate(p, *last);
    if (f < 0) return false;
    const int above = AbovePlane(ws_.facets[f], pts_, p);
    if (above == 0) return false;  // coplanar with a facet: let CGAL decide
    if (above < 0) {               // inside the hull, now and forever
      *last = f;
      return true;
    }
    // Visible region by flood fill; its boundary edges form the horizon.
    if (++ws_.stamp == 0) {  // wrapped after 2^32 insertions: clear the marks
      for (Facet& g : ws_.facets) g.stamp = 0;
      ws_.stamp = 1;
    }
    const std::uint32_t stamp = ws_.stamp;
    ws_.visible.clear();
    ws_.horizon.clear();
    ws_.stack.clear();
    ws_.facets[f].stamp = stamp;
    ws_.facets[f].above = true;
    ws_.stack.push_back(f);
    ws_.visible.push_back(f);
    while (!ws_.stack.empty()) {
      const int g = ws_.stack.back();
      ws_.stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const int h = ws_.facets[g].nb[k];
        Facet& H = ws_.facets[h];
        if (H.stamp != stamp) {
          const int s = AbovePlane(H, pts_, p);
          if (s == 0) return false;  // coplanar: let CGAL decide
          H.stamp = stamp;
          H.above = s > 0;
          if (H.above) {
            ws_.stack.push_back(h);
            ws_.visible.push_back(h);
          }
        }
        if (!H.above) ws_.horizon.push_back({h, ws_.facets[g].v[k], ws_.facets[g].v[(k + 1) % 3]});
      }
    }
    for (int g : ws_.visible) {
      ws_.facets[g].alive = false;
      --alive_;
    }
    // Cone the horizon to p.
    bool simple = true;
    for (const auto& e : ws_.horizon) {
      const int outer = e[0], a = e[1], b = e[2];
      const int nf = NewFacet(a, b, p);
      ws_.facets[nf].nb[0] = outer;
      Facet& O = ws_.facets[outer];
      for (int j = 0; j < 3; ++j) {
        if (O.v[j] == b && O.v[(j + 1) % 3] == a) O.nb[j] = nf;
      }
      if (ws_.new_facet_from[a] != -1 || ws_.new_facet_to[b] != -1) simple = false;
      ws_.new_facet_from[a] = nf;
      ws_.new_facet_to[b] = nf;
    }
    for (const auto& e : ws_.horizon) {
      const int a = e[1], b = e[2];
      const int nf = ws_.new_facet_from[a];
      ws_.facets[nf].nb[1] = ws_.new_facet_from[b];  // edge b -> p
      ws_.facets[nf].nb[2] = ws_.new_facet_to[a];    // edge p -> a
      if (ws_.new_facet_from[b] < 0 || ws_.new_facet_to[a] < 0) simple = false;
    }
    const int any_new = ws_.horizon.empty() ? -1 : ws_.new_facet_from[ws_.horizon.front()[1]];
    for (const auto& e : ws_.horizon) {
      ws_.new_facet_from[e[1]] = -1;
      ws_.new_facet_to[e[2]] = -1;
    }
    // Freed slots are reused only after the links above were made.
    for (int g : ws_.visible) ws_.free_facets.push_back(g);
    if (!simple || any_new < 0) return false;
    *last = any_new;
    return true;
  }

  const Points& pts_;
  HullWorkspace& ws_;
  Vec3 centre_ = Vec3::Zero();
  int alive_ = 0;
};

}  // namespace

HullStatus IncrementalHull(const Points& points, HullWorkspace* workspace, std::vector<int>* vertices,
                           std::vector<std::array<int, 3>>* faces) {
  return Builder(points, workspace).Run(vertices, faces);
}

}  // namespace ovpc::internal
