#include "ovpc/core/free_space_mesh.h"

#include <algorithm>
#include <utility>

namespace ovpc {

MeshTopology CheckTopology(const std::vector<Triangle>& triangles) {
  MeshTopology topo;
  topo.num_faces = triangles.size();
  std::vector<std::pair<int, int>> directed;
  directed.reserve(3 * triangles.size());
  std::vector<int> used;
  used.reserve(3 * triangles.size());
  topo.no_degenerate_faces = true;
  for (const Triangle& t : triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) topo.no_degenerate_faces = false;
    for (int k = 0; k < 3; ++k) {
      directed.emplace_back(t[k], t[(k + 1) % 3]);
      used.push_back(t[k]);
    }
  }
  std::sort(used.begin(), used.end());
  topo.num_vertices = static_cast<std::size_t>(std::unique(used.begin(), used.end()) - used.begin());

  std::sort(directed.begin(), directed.end());
  const bool directed_unique = std::adjacent_find(directed.begin(), directed.end()) == directed.end();
  bool reverse_present = true;
  for (const auto& e : directed) {
    if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(e.second, e.first))) {
      reverse_present = false;
      break;
    }
  }
  // Undirected edge multiplicities.
  std::vector<std::pair<int, int>> undirected;
  undirected.reserve(directed.size());
  for (const auto& e : directed) undirected.emplace_back(std::min(e.first, e.second), std::max(e.first, e.second));
  std::sort(undirected.begin(), undirected.end());
  bool two_each = !undirected.empty();
  std::size_t edges = 0;
  for (std::size_t i = 0; i < undirected.size();) {
    std::size_t j = i;
    while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
    if (j - i != 2) two_each = false;
    ++edges;
    i = j;
  }
  topo.num_edges = edges;
  topo.every_edge_in_two_faces = two_each;
  topo.consistently_oriented = directed_unique && reverse_present && !triangles.empty();
  topo.euler_characteristic = static_cast<int>(topo.num_vertices) - static_cast<int>(topo.num_edges) +
                              static_cast<int>(topo.num_faces);
  return topo;
}

double EnclosedVolume(const Points& vertices, const std::vector<Triangle>& triangles) {
  if (vertices.empty()) return 0.0;
  Vec3 ref = Vec3::Zero();
  for (const Vec3& v : vertices) ref += v;
  ref /= static_cast<double>(vertices.size());
  double six_volume = 0.0;
  for (const Triangle& t : triangles) {
    const Vec3 a = vertices[t[0]] - ref;
    const Vec3 b = vertices[t[1]] - ref;
    const Vec3 c = vertices[t[2]] - ref;
    six_volume += a.dot(b.cross(c));
  }
  // Normals point inwards, so the outward-normal formula gives the negative volume.
  return -six_volume / 6.0;
}

}  // namespace ovpc
