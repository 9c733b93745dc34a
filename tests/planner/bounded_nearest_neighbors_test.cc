#include "bounded_nearest_neighbors.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

namespace ovpc::planner::internal {
namespace {

namespace ob = ompl::base;
using Se2State = ob::SE2StateSpace::StateType;
using Tree = BoundedNearestNeighbors<ob::State*>;
constexpr double kRadius = 3.7;

Pose2 PoseOf(ob::State* const& state) {
  const auto* s = state->as<Se2State>();
  return Pose2{s->getX(), s->getY(), s->getYaw()};
}

// Random states in a 40 m square, as the planner's trees hold them, and a tree over them whose
// distance function counts its calls.
class BoundedNearestNeighborsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    space_ = std::make_shared<ob::ReedsSheppStateSpace>(kRadius);
    ob::RealVectorBounds bounds(2);
    bounds.setLow(-20.0);
    bounds.setHigh(20.0);
    space_->setBounds(bounds);
    tree_ = std::make_unique<Tree>(PoseOf, kRadius);
    tree_->setDistanceFunction([this](ob::State* const& a, ob::State* const& b) {
      ++distances_;
      return space_->distance(a, b);
    });
  }
  void TearDown() override {
    for (ob::State* s : states_) space_->freeState(s);
  }
  ob::State* Random() {
    std::uniform_real_distribution<double> xy(-20.0, 20.0), yaw(-kPi, kPi);
    ob::State* s = space_->allocState();
    s->as<Se2State>()->setXY(xy(rng_), xy(rng_));
    s->as<Se2State>()->setYaw(yaw(rng_));
    states_.push_back(s);
    return s;
  }
  // Every element by exact distance to `query`, nearest first (the reference answer).
  std::vector<std::pair<double, ob::State*>> Exhaustive(ob::State* query, const std::vector<ob::State*>& elements) const {
    std::vector<std::pair<double, ob::State*>> all;
    for (ob::State* e : elements) all.emplace_back(space_->distance(query, e), e);
    std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return all;
  }

  std::shared_ptr<ob::ReedsSheppStateSpace> space_;
  std::unique_ptr<Tree> tree_;
  std::vector<ob::State*> states_;
  std::mt19937 rng_{11};
  long distances_ = 0;
};

TEST_F(BoundedNearestNeighborsTest, TheBoundNeverExceedsTheReedsSheppLength) {
  for (int k = 0; k < 5000; ++k) {
    ob::State* a = Random();
    ob::State* b = Random();
    const auto* sa = a->as<Se2State>();
    if (k % 3 == 0) {  // near pairs too, where the heading term dominates
      b->as<Se2State>()->setXY(sa->getX() + 0.3, sa->getY() - 0.2);
    } else if (k % 3 == 1) {  // beside each other, up to two turning radii apart, about parallel
      const double side = std::uniform_real_distribution<double>(-2.0 * kRadius, 2.0 * kRadius)(rng_);
      const double ahead = std::uniform_real_distribution<double>(-0.5, 0.5)(rng_);
      const double c = std::cos(sa->getYaw()), s = std::sin(sa->getYaw());
      b->as<Se2State>()->setXY(sa->getX() + c * ahead - s * side, sa->getY() + s * ahead + c * side);
      b->as<Se2State>()->setYaw(sa->getYaw() + std::uniform_real_distribution<double>(-0.3, 0.3)(rng_));
    }
    ASSERT_LE(Tree::LowerBound(PoseOf(a), PoseOf(b), kRadius), space_->distance(a, b)) << "pair " << k;
  }
}

TEST_F(BoundedNearestNeighborsTest, TheBoundHoldsForStatesMicrometresApart) {
  // A short arc between nearly equal states far from the origin, where the sideways bound is steepest
  // and the coordinates' rounding largest (a review found an overestimate here).
  const auto state = [this](double x, double y, double yaw) {
    ob::State* s = space_->allocState();
    s->as<Se2State>()->setXY(x, y);
    s->as<Se2State>()->setYaw(yaw);
    states_.push_back(s);
    return s;
  };
  ob::State* q = state(46.218902775620094, 18.285285406921169, 2.2705289279141816);
  ob::State* e1 = state(46.218901962160558, 18.285286373218312, 2.270529269295233);
  EXPECT_LE(Tree::LowerBound(PoseOf(e1), PoseOf(q), kRadius), space_->distance(e1, q));
  std::uniform_real_distribution<double> tiny(-2e-6, 2e-6), xy(-60.0, 60.0), yaw(-kPi, kPi);
  for (int k = 0; k < 20000; ++k) {
    ob::State* a = state(xy(rng_), xy(rng_), yaw(rng_));
    const auto* sa = a->as<Se2State>();
    ob::State* b = state(sa->getX() + tiny(rng_), sa->getY() + tiny(rng_), sa->getYaw() + tiny(rng_));
    ASSERT_LE(Tree::LowerBound(PoseOf(b), PoseOf(a), kRadius), space_->distance(b, a)) << "pair " << k;
    ASSERT_LE(Tree::LowerBound(PoseOf(a), PoseOf(b), kRadius), space_->distance(a, b)) << "pair " << k;
  }
}

TEST_F(BoundedNearestNeighborsTest, AnswersAsAnExhaustiveSearchWithFewerDistances) {
  std::vector<ob::State*> elements;
  for (int i = 0; i < 600; ++i) {
    elements.push_back(Random());
    tree_->add(elements.back());
  }
  ASSERT_EQ(tree_->size(), elements.size());
  long exhaustive = 0;
  distances_ = 0;
  for (int q = 0; q < 200; ++q) {
    ob::State* query = Random();
    const auto expected = Exhaustive(query, elements);
    exhaustive += static_cast<long>(elements.size());
    EXPECT_EQ(tree_->nearest(query), expected.front().second) << "query " << q;

    std::vector<ob::State*> k_nearest;
    tree_->nearestK(query, 7, k_nearest);
    ASSERT_EQ(k_nearest.size(), 7u);
    for (std::size_t i = 0; i < k_nearest.size(); ++i) EXPECT_EQ(k_nearest[i], expected[i].second) << "query " << q;

    const double radius = expected[12].first;  // the 13 nearest, sorted
    std::vector<ob::State*> within;
    tree_->nearestR(query, radius, within);
    ASSERT_EQ(within.size(), 13u) << "query " << q;
    for (std::size_t i = 0; i < within.size(); ++i) EXPECT_EQ(within[i], expected[i].second) << "query " << q;
  }
  // The point of the structure: most elements are ruled out by their bound.
  EXPECT_LT(distances_, exhaustive / 3) << distances_ << " distances against " << exhaustive;
}

TEST_F(BoundedNearestNeighborsTest, RemoveListAndClear) {
  std::vector<ob::State*> elements;
  for (int i = 0; i < 20; ++i) {
    elements.push_back(Random());
    tree_->add(elements.back());
  }
  std::vector<ob::State*> listed;
  tree_->list(listed);
  EXPECT_EQ(listed, elements);  // in the order added

  ob::State* query = elements[5];
  EXPECT_EQ(tree_->nearest(query), elements[5]);  // an element is its own nearest
  EXPECT_TRUE(tree_->remove(elements[5]));
  EXPECT_FALSE(tree_->remove(elements[5]));
  EXPECT_EQ(tree_->size(), 19u);
  EXPECT_NE(tree_->nearest(query), elements[5]);

  std::vector<ob::State*> k_nearest;
  tree_->nearestK(query, 100, k_nearest);
  EXPECT_EQ(k_nearest.size(), 19u);  // k larger than the tree: all of it

  tree_->clear();
  EXPECT_EQ(tree_->size(), 0u);
  EXPECT_THROW(tree_->nearest(query), ompl::Exception);
  tree_->nearestK(query, 3, k_nearest);
  EXPECT_TRUE(k_nearest.empty());
}

}  // namespace
}  // namespace ovpc::planner::internal
