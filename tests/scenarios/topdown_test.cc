// The top-down figure of a made-up run: where the world lands in the picture (both ways), the axis
// ticks, the legend's samples, the stall and rocking marks, the font's coverage, the same bytes for
// the same run, and bad input that does not crash.
#include "ovpc/scenarios/topdown.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "bitmap_font.h"
#include "ovpc/scenarios/report.h"
#include "ovpc/scenarios/scenario_yaml.h"

namespace ovpc::scenarios {
namespace {

// Route 0..30 m along x, goal circle 26..30 x -2..2; with the 10 m margin the plot spans x -10..40
// and y -12..12: 50 m by 24 m at 20 pixels a metre, ticks every 10 m.
const char* const kMadeUp = R"(name: made_up
time_limit_s: 60
terrain: {kind: flat, size_m: [80, 40]}
objects:
  - box: {x_m: 15.0, y_m: 6.0, length_m: 2.0, width_m: 2.0}
route: [[0, 0], [30, 0]]
criteria:
  goal: {x_m: 28.0, y_m: 0.0, radius_m: 2.0}
  forbidden: [{name: pit, min_m: [5, -8], max_m: [9, -4]}]
)";

// Drives 10 m east (0-10 s), stands 15 s at x = 10, drives on to x = 20 (25-35 s), then rocks back
// and forth there for 20 s (0.8 m back, 0.8 m forward, every 4 s; the first reversal at 35 s).
RunResult MadeUpRun() {
  RunResult r;
  r.scenario = "made_up";
  r.seed = 3;
  r.end_reason = "time limit";
  r.criteria.push_back({"goal_reached", "", "no", false});
  double x = 0.0;
  for (int i = 0; i <= 550; ++i) {
    TrajectorySample s;
    s.time_s = 0.1 * i;
    const double t = s.time_s;
    s.speed_mps = t < 10 ? 1.0 : t < 25 ? 0.0 : t < 35 ? 1.0 : (std::fmod(t - 35, 4.0) < 2.0 ? -0.4 : 0.4);
    s.T_W_B.translation() = Eigen::Vector3d(x, 0, 0);
    x += 0.1 * s.speed_mps;
    r.trajectory.push_back(s);
  }
  r.sim_time_s = 55.0;
  for (int i = 0; i < 200; ++i) r.map_points.push_back({Vec3(0.1 * i, 3.0, 0.0), i % 2 == 0});
  return r;
}

std::array<std::uint8_t, 3> PixelAt(const sim::Image& image, int x, int y) {
  const std::uint8_t* p = image.Pixel(x, y);
  return {p[0], p[1], p[2]};
}

TEST(BitmapFontTest, EveryPrintableAsciiCharacterAndTheDegreeSignHaveAGlyph) {
  for (char32_t c = 32; c < 127; ++c) EXPECT_NE(internal::FindGlyph(c), nullptr) << "character " << int(c);
  EXPECT_NE(internal::FindGlyph(U'\u00B0'), nullptr);
  EXPECT_NE(internal::FindGlyph(U'\u00D7'), nullptr);
  EXPECT_EQ(internal::FindGlyph(U'\uFFFD'), nullptr);
  for (char32_t c = 32; c < 127; ++c) {
    const std::uint8_t* rows = internal::FindGlyph(c);
    for (int r = 0; r < internal::kGlyphHeight; ++r) EXPECT_LT(rows[r], 1 << internal::kGlyphWidth);
  }
  EXPECT_EQ(internal::DecodeUtf8("30\xC2\xB0"), U"30\u00B0");
  EXPECT_EQ(internal::DecodeUtf8("a\xFF" "b\xC2"), U"a\uFFFDb\uFFFD");
  EXPECT_EQ(internal::TextWidth("t=1"), 17);
  EXPECT_EQ(internal::TextWidth(""), 0);
}

TEST(TopdownTest, EveryTextOfThePictureHasGlyphs) {
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), MadeUpRun());
  ASSERT_GT(f.texts.size(), 20u);
  for (const std::string& text : f.texts) {
    for (char32_t c : internal::DecodeUtf8(text)) EXPECT_NE(internal::FindGlyph(c), nullptr) << "in \"" << text << "\"";
  }
}

TEST(TopdownTest, TickStepsAreRound) {
  EXPECT_EQ(TickStep(50.0), 10.0);
  EXPECT_EQ(TickStep(80.0), 10.0);
  EXPECT_EQ(TickStep(81.0), 20.0);
  EXPECT_EQ(TickStep(20.0), 5.0);
  EXPECT_EQ(TickStep(300.0), 50.0);
  EXPECT_NEAR(TickStep(0.5), 0.1, 1e-12);
  EXPECT_EQ(TickStep(0.0), 1.0);
  EXPECT_EQ(TickStep(std::nan("")), 1.0);
}

TEST(TopdownTest, WorldAndPixelsMapBothWays) {
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), MadeUpRun());
  const TopdownView& v = f.view;
  EXPECT_EQ(v.px_per_m, 20.0);
  EXPECT_EQ(v.width_px, 1000);
  EXPECT_EQ(v.height_px, 480);
  EXPECT_EQ(v.ToPixel({-10, 12}), Eigen::Vector2d(v.left_px, v.top_px));   // top-left corner
  EXPECT_EQ(v.ToPixel({0, 0}), Eigen::Vector2d(v.left_px + 200, v.top_px + 240));
  EXPECT_EQ(v.ToPixel({40, -12}), Eigen::Vector2d(v.left_px + 1000, v.top_px + 480));
  const Eigen::Vector2d centre = v.ToWorld({v.left_px + 200.5, v.top_px + 240.5});
  EXPECT_NEAR(centre.x(), 0.025, 1e-12);
  EXPECT_NEAR(centre.y(), -0.025, 1e-12);
  for (const Eigen::Vector2d& w : {Eigen::Vector2d(3.7, -2.2), Eigen::Vector2d(-9.99, 9.99)}) {
    EXPECT_LT((v.ToWorld(v.ToPixel(w)) - w).norm(), 1e-12);
  }
}

TEST(TopdownTest, TicksSitAtTheirPixelColumnsAndRows) {
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), MadeUpRun());
  const TopdownView& v = f.view;
  EXPECT_EQ(f.tick_step_m, 10.0);
  ASSERT_EQ(f.x_ticks.size(), 6u);
  ASSERT_EQ(f.y_ticks.size(), 3u);
  const int bottom = v.top_px + v.height_px;
  for (std::size_t k = 0; k < f.x_ticks.size(); ++k) {
    EXPECT_EQ(f.x_ticks[k].value_m, -10.0 + 10.0 * k);
    const int column = v.left_px + 200 * static_cast<int>(k);
    EXPECT_EQ(f.x_ticks[k].pixel, column);
    EXPECT_EQ(PixelAt(f.image, column, bottom + 3), (std::array<std::uint8_t, 3>{0, 0, 0})) << "tick " << k;
    EXPECT_EQ(PixelAt(f.image, column + 2, bottom + 3), (std::array<std::uint8_t, 3>{255, 255, 255})) << "tick " << k;
  }
  for (std::size_t k = 0; k < f.y_ticks.size(); ++k) {
    EXPECT_EQ(f.y_ticks[k].value_m, -10.0 + 10.0 * k);
    const int row = v.top_px + 440 - 200 * static_cast<int>(k);
    EXPECT_EQ(f.y_ticks[k].pixel, row);
    EXPECT_EQ(PixelAt(f.image, v.left_px - 4, row), (std::array<std::uint8_t, 3>{0, 0, 0})) << "tick " << k;
    EXPECT_EQ(PixelAt(f.image, v.left_px - 4, row + 2), (std::array<std::uint8_t, 3>{255, 255, 255})) << "tick " << k;
  }
}

TEST(TopdownTest, TheLegendBoxHoldsASampleOfEachMarkInItsColour) {
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), MadeUpRun());
  EXPECT_GE(f.legend.x, f.view.left_px + f.view.width_px) << "the legend covers no part of the plot";
  EXPECT_LE(f.legend.x + f.legend.width, f.image.width);
  EXPECT_LE(f.legend.y + f.legend.height, f.image.height);
  ASSERT_EQ(f.legend_entries.size(), 12u);
  for (const char* name : {"route", "path driven", "start pose", "end pose", "goal (radius 2.0 m)", "objects",
                           "map: traversable", "map: not traversable", "forbidden region"}) {
    EXPECT_TRUE(std::any_of(f.legend_entries.begin(), f.legend_entries.end(),
                            [&](const LegendEntry& e) { return e.label == name; }))
        << name;
  }
  for (const LegendEntry& e : f.legend_entries) {
    const PixelBox& b = e.sample;
    EXPECT_TRUE(f.legend.Contains(b.x, b.y) && f.legend.Contains(b.x + b.width - 1, b.y + b.height - 1)) << e.label;
    int found = 0;
    for (int y = b.y; y < b.y + b.height; ++y)
      for (int x = b.x; x < b.x + b.width; ++x) found += PixelAt(f.image, x, y) == e.colour;
    EXPECT_GE(found, 3) << e.label << ": its colour in its sample";
  }
}

TEST(TopdownTest, StallAndRockingAreMarkedWhereAndWhenTheyHappened) {
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), MadeUpRun());
  ASSERT_EQ(f.spells.size(), 2u);
  const Spell& stall = f.spells[0];
  EXPECT_EQ(stall.kind, "stall");
  EXPECT_NEAR(stall.start_s, 10.0, 0.05);
  EXPECT_NEAR(stall.at_m.x(), 10.0, 0.15);
  const Spell& rocking = f.spells[1];
  EXPECT_EQ(rocking.kind, "rocking");
  EXPECT_NEAR(rocking.start_s, 35.0, 0.05);
  EXPECT_NEAR(rocking.at_m.x(), 20.0, 0.15);
  // The marks' centres: world (10, 0) is pixel (left + 400, top + 240).
  const Eigen::Vector2d at = f.view.ToPixel(stall.at_m);
  EXPECT_NEAR(at.x(), f.view.left_px + 400, 3.0);
  EXPECT_NEAR(at.y(), f.view.top_px + 240, 1e-9);
  const auto colour_at = [&](const Spell& s) {
    const Eigen::Vector2d p = f.view.ToPixel(s.at_m);
    return PixelAt(f.image, static_cast<int>(p.x()), static_cast<int>(p.y()));
  };
  EXPECT_EQ(colour_at(stall), f.legend_entries[10].colour);
  EXPECT_EQ(colour_at(rocking), f.legend_entries[11].colour);
  EXPECT_NE(std::find(f.texts.begin(), f.texts.end(), "t=10.0 s"), f.texts.end());
  EXPECT_NE(std::find(f.texts.begin(), f.texts.end(), "t=35.0 s"), f.texts.end());
}

TEST(TopdownTest, TheSameRunGivesTheSameBytes) {
  const Scenario s = ParseScenario(kMadeUp, "made_up.yaml");
  const std::string a = ::testing::TempDir() + "/topdown_a.png", b = ::testing::TempDir() + "/topdown_b.png";
  WriteTopdownPng(s, MadeUpRun(), a);
  WriteTopdownPng(s, MadeUpRun(), b);
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string bytes_a{std::istreambuf_iterator<char>(fa), {}}, bytes_b{std::istreambuf_iterator<char>(fb), {}};
  EXPECT_GT(bytes_a.size(), 1000u);
  EXPECT_EQ(bytes_a, bytes_b);
}

TEST(TopdownTest, NonFiniteAndFarValuesDoNotBreakIt) {
  RunResult r = MadeUpRun();
  r.trajectory[5].T_W_B.translation().x() = std::nan("");
  r.trajectory[6].T_W_B.translation().y() = HUGE_VAL;
  r.trajectory[7].T_W_B.translation().x() = 1e300;
  r.trajectory[8].T_W_B.translation() = Eigen::Vector3d(1.7e308, -1.7e308, 0);
  r.map_points.push_back({Vec3(std::nan(""), 0, 0), true});
  r.map_points.push_back({Vec3(-HUGE_VAL, 1e308, 0), false});
  r.scenario = "odd \xFF name";
  r.sim_time_s = std::nan("");
  const TopdownFigure f = DrawTopdown(ParseScenario(kMadeUp, "made_up.yaml"), r);
  EXPECT_LE(f.view.width_px, 2000);
  EXPECT_LE(f.view.height_px, 2000);
  EXPECT_EQ(f.view.px_per_m, 20.0) << "far places do not size the picture";
  EXPECT_EQ(f.view.width_px, 1000);
  const TopdownFigure empty = DrawTopdown(Scenario{}, RunResult{});
  EXPECT_GT(empty.image.width, 100);
  EXPECT_TRUE(empty.spells.empty());
}

}  // namespace
}  // namespace ovpc::scenarios
