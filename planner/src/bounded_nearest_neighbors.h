// Exact nearest neighbours for the planner's search trees, pruned by a cheap lower bound of the
// distance. Private to the planner (it needs OMPL's headers).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <ompl/datastructures/NearestNeighbors.h>
#include <ompl/util/Exception.h>

#include "ovpc/core/types.h"
#include "ovpc/planner/path.h"

namespace ovpc::planner::internal {

/// Nearest-neighbour structure for RRTConnect's trees in a Reeds-Shepp space, where a distance
/// (a Reeds-Shepp path length) is expensive: it solves every path family, with its trigonometry.
///
/// Every element keeps a planar pose. Three lower bounds of the Reeds-Shepp length L between two
/// poses hold, and a query uses the largest: the straight line between the positions; the turning
/// radius r times the heading change (the path turns at most 1/r per metre); and the sideways offset
/// d of either pose in the frame of the other. Along the path the heading has turned at most s/r
/// after s metres, so the sideways offset grows at most like sin(min(s/r, pi/2)); integrated,
/// d <= r (1 - cos(L/r)) while L <= r pi/2, and d <= r + (L - r pi/2) beyond, which bounds L from
/// below. Reversing the path gives the same from the other pose. A query computes the exact distance
/// only for elements whose bound is below the best distance so far, so it returns the same nearest
/// element as an exhaustive search (the first-added one among exactly equal distances). Adding an
/// element costs no distance at all. For the trees of a local plan (at most a few thousand states)
/// this takes a fraction of the distances a metric tree (OMPL's GNAT default) needs, and it does not
/// depend on a metric tree's balance.
///
/// The lower bound must hold for the distance function given by setDistanceFunction: Reeds-Shepp
/// length with `turning_radius_m`, or anything longer.
template <typename T>
class BoundedNearestNeighbors final : public ompl::NearestNeighbors<T> {
 public:
  /// The planar pose of an element (the planner's Pose2; any yaw, not only normalised ones).
  using PoseOf = std::function<Pose2(const T&)>;

  BoundedNearestNeighbors(PoseOf pose_of, double turning_radius_m)
      : pose_of_(std::move(pose_of)), turning_radius_m_(turning_radius_m) {}

  /// A lower bound of the Reeds-Shepp length from `a` to `b`, slightly reduced so that rounding in
  /// either computation cannot turn it into an overestimate.
  static double LowerBound(const Pose2& a, const Pose2& b, double turning_radius_m) {
    return LowerBound(Key(a), Key(b), turning_radius_m);
  }

  bool reportsSortedResults() const override { return true; }
  void clear() override { elements_.clear(); }
  void add(const T& data) override { elements_.push_back(Element{data, Key(pose_of_(data))}); }
  bool remove(const T& data) override {
    const auto it = std::find_if(elements_.begin(), elements_.end(), [&](const Element& e) { return e.data == data; });
    if (it == elements_.end()) return false;
    elements_.erase(it);
    return true;
  }
  std::size_t size() const override { return elements_.size(); }
  void list(std::vector<T>& data) const override {
    data.clear();
    data.reserve(elements_.size());
    for (const Element& e : elements_) data.push_back(e.data);
  }

  T nearest(const T& data) const override {
    if (elements_.empty()) throw ompl::Exception("BoundedNearestNeighbors: no elements");
    const Key q(pose_of_(data));
    // Candidates by increasing bound; the scan stops at the first bound above the best distance.
    order_.resize(elements_.size());
    for (std::size_t i = 0; i < elements_.size(); ++i) order_[i] = {LowerBound(q, elements_[i].pose, turning_radius_m_), i};
    std::sort(order_.begin(), order_.end());
    // Element first, query second: RRTConnect then asks the state space for the distance and the path
    // from the nearest element to the query, which the planner's space keeps from this scan.
    std::size_t best = order_[0].second;
    double best_d = this->distFun_(elements_[best].data, data);
    for (std::size_t k = 1; k < order_.size() && order_[k].first <= best_d; ++k) {
      const std::size_t i = order_[k].second;
      const double d = this->distFun_(elements_[i].data, data);
      if (d < best_d || (d == best_d && i < best)) best = i, best_d = d;
    }
    return elements_[best].data;
  }

  void nearestK(const T& data, std::size_t k, std::vector<T>& nbh) const override {
    nbh.clear();
    if (k == 0 || elements_.empty()) return;
    const Key q(pose_of_(data));
    // (distance, index) of the k best so far, as a max-heap.
    std::vector<std::pair<double, std::size_t>> heap;
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      if (heap.size() == k && LowerBound(q, elements_[i].pose, turning_radius_m_) > heap.front().first) continue;
      const double d = this->distFun_(data, elements_[i].data);
      if (heap.size() < k) {
        heap.emplace_back(d, i);
        std::push_heap(heap.begin(), heap.end());
      } else if (std::make_pair(d, i) < heap.front()) {
        std::pop_heap(heap.begin(), heap.end());
        heap.back() = {d, i};
        std::push_heap(heap.begin(), heap.end());
      }
    }
    std::sort_heap(heap.begin(), heap.end());
    for (const auto& [d, i] : heap) nbh.push_back(elements_[i].data);
  }

  void nearestR(const T& data, double radius, std::vector<T>& nbh) const override {
    nbh.clear();
    const Key q(pose_of_(data));
    std::vector<std::pair<double, std::size_t>> found;
    for (std::size_t i = 0; i < elements_.size(); ++i) {
      if (LowerBound(q, elements_[i].pose, turning_radius_m_) > radius) continue;
      const double d = this->distFun_(data, elements_[i].data);
      if (d <= radius) found.emplace_back(d, i);
    }
    std::sort(found.begin(), found.end());
    for (const auto& [d, i] : found) nbh.push_back(elements_[i].data);
  }

 private:
  // A pose with its heading's cosine and sine.
  struct Key {
    Key() = default;
    explicit Key(const Pose2& p)
        : x(p.x_m), y(p.y_m), yaw(p.yaw_rad), c(std::cos(p.yaw_rad)), s(std::sin(p.yaw_rad)) {}
    double x = 0.0, y = 0.0, yaw = 0.0, c = 1.0, s = 0.0;
  };
  struct Element {
    T data;
    Key pose;
  };

  static double LowerBound(const Key& a, const Key& b, double r) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double euclid = std::sqrt(dx * dx + dy * dy);
    double turn = std::fmod(std::abs(b.yaw - a.yaw), 2.0 * kPi);
    if (turn > kPi) turn = 2.0 * kPi - turn;
    // The offset less a slack for the rounding of the coordinates: near zero the bound is steep
    // (an error e in the offset moves it by about sqrt(2 r e)). r acos(1 - d/r) is written as
    // 2 r asin(sqrt(d / 2r)), which is accurate for small d.
    const double slack = 1e-9 * (1.0 + std::abs(a.x) + std::abs(a.y));
    const double side =
        std::max(0.0, std::max(std::abs(a.c * dy - a.s * dx), std::abs(b.c * dy - b.s * dx)) - slack);
    const double sideways = side <= r ? 2.0 * r * std::asin(std::sqrt(side / (2.0 * r))) : r * 0.5 * kPi + (side - r);
    return std::max({euclid, r * turn, sideways}) * (1.0 - 1e-9) - 1e-9;
  }
  PoseOf pose_of_;
  double turning_radius_m_;
  std::vector<Element> elements_;
  mutable std::vector<std::pair<double, std::size_t>> order_;  // scratch of nearest(); one thread per tree
};

}  // namespace ovpc::planner::internal
