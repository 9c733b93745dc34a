// The top-down figure of a run: a raster with the project's bitmap font, written by libpng.
#include "ovpc/scenarios/topdown.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bitmap_font.h"
#include "format.h"
#include "ovpc/scenarios/report.h"
#include "ovpc/sim/terrain.h"
#include "ovpc/sim/world.h"

namespace ovpc::scenarios {
namespace {

using internal::Fixed;
using Colour = std::array<std::uint8_t, 3>;
using Px = Eigen::Vector2d;  // a place in the picture, pixels (continuous)

constexpr Colour kRoute{40, 80, 220}, kPath{0, 0, 0}, kStart{0, 190, 230}, kEnd{200, 0, 200}, kGoal{230, 170, 0},
    kObject{70, 60, 50}, kRoof{120, 90, 170}, kTraversable{30, 170, 60}, kNotTraversable{210, 40, 40},
    kForbidden{230, 120, 0}, kStall{220, 0, 60}, kRocking{0, 150, 150}, kInk{0, 0, 0}, kGreyInk{90, 90, 90},
    kWhite{255, 255, 255};
constexpr int kMargin = 10;       // around the figure
constexpr int kTick = 5;          // tick length
constexpr int kTop = 62;          // title, subtitle and the y axis' name above the plot
constexpr int kBottom = 44;       // tick labels and the x axis' name below it
constexpr int kLegendGap = 20;    // between the plot and the legend
constexpr int kRow = 16;          // legend line height
constexpr int kSampleW = 28;      // legend sample width
constexpr std::size_t kMaxSpells = 40;  // marked at most (a pathological run stays legible and cheap)

double HeadingRad(const Eigen::Isometry3d& T) { return std::atan2(T.linear()(1, 0), T.linear()(0, 0)); }

// A double as a pixel index, bounded so that any finite or infinite value converts safely.
int ToInt(double v) { return std::isnan(v) ? -1 : static_cast<int>(std::floor(std::clamp(v, -1e6, 1e6))); }

// Pixels with blending, clipped to a box, and text in the bitmap font.
class Raster {
 public:
  Raster(int width, int height) {
    image_.width = width;
    image_.height = height;
    image_.rgb.assign(static_cast<std::size_t>(width) * height * 3, 255);
    clip_ = {0, 0, width, height};
  }
  void Clip(const PixelBox& box) { clip_ = box; }
  void Unclip() { clip_ = {0, 0, image_.width, image_.height}; }
  void Set(int px, int py, const Colour& c, double alpha = 1.0) {
    if (!clip_.Contains(px, py)) return;
    std::uint8_t* p = image_.rgb.data() + 3 * (static_cast<std::size_t>(py) * image_.width + px);
    for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(p[k] * (1 - alpha) + c[k] * alpha));
  }
  void Fill(const PixelBox& b, const Colour& c, double alpha = 1.0) {
    for (int y = std::max(b.y, clip_.y); y < std::min(b.y + b.height, clip_.y + clip_.height); ++y)
      for (int x = std::max(b.x, clip_.x); x < std::min(b.x + b.width, clip_.x + clip_.width); ++x) Set(x, y, c, alpha);
  }
  void Frame(const PixelBox& b, const Colour& c) {
    Fill({b.x, b.y, b.width, 1}, c);
    Fill({b.x, b.y + b.height - 1, b.width, 1}, c);
    Fill({b.x, b.y, 1, b.height}, c);
    Fill({b.x + b.width - 1, b.y, 1, b.height}, c);
  }
  // The pixels whose centres lie within `radius` of `centre`.
  void Disc(const Px& centre, double radius, const Colour& c, double alpha = 1.0, double inner = -1.0) {
    if (!centre.allFinite() || !(radius >= 0)) return;
    for (int y = ToInt(centre.y() - radius); y <= ToInt(centre.y() + radius); ++y) {
      if (y < clip_.y || y >= clip_.y + clip_.height) continue;
      for (int x = std::max(clip_.x, ToInt(centre.x() - radius)); x <= std::min(clip_.x + clip_.width, ToInt(centre.x() + radius)); ++x) {
        const double d = std::hypot(x + 0.5 - centre.x(), y + 0.5 - centre.y());
        if (d <= radius && d > inner) Set(x, y, c, alpha);
      }
    }
  }
  // A line `radius` pixels either side (0: one pixel wide), the part inside the clip box only.
  void Line(Px a, Px b, int radius, const Colour& c) {
    if (!a.allFinite() || !b.allFinite() || !ClipSegment(&a, &b, radius + 1.0)) return;
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() * 2)));
    for (int i = 0; i <= steps; ++i) {
      const Px p = a + (b - a) * (double(i) / steps);
      if (radius == 0) Set(ToInt(p.x()), ToInt(p.y()), c);
      else Disc(p, radius + 0.3, c);
    }
  }
  // A filled convex polygon and its outline.
  void Polygon(const std::vector<Px>& corners, const Colour& fill, const Colour& outline) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const Px& p : corners) {
      if (!p.allFinite()) return;
      x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    }
    for (int y = std::max(clip_.y, ToInt(y0)); y <= std::min(clip_.y + clip_.height - 1, ToInt(y1)); ++y) {
      for (int x = std::max(clip_.x, ToInt(x0)); x <= std::min(clip_.x + clip_.width - 1, ToInt(x1)); ++x) {
        const Px q(x + 0.5, y + 0.5);
        bool pos = false, neg = false;
        for (std::size_t i = 0; i < corners.size(); ++i) {
          const Px e = corners[(i + 1) % corners.size()] - corners[i], d = q - corners[i];
          const double cross = e.x() * d.y() - e.y() * d.x();
          pos |= cross > 0, neg |= cross < 0;
        }
        if (!(pos && neg)) Set(x, y, fill);
      }
    }
    for (std::size_t i = 0; i < corners.size(); ++i) Line(corners[i], corners[(i + 1) % corners.size()], 0, outline);
  }
  // Text with its top-left corner at (x, y); unknown characters show as boxes.
  void Text(int x, int y, const std::string& text, const Colour& c, int scale = 1) {
    texts_.push_back(text);
    for (char32_t code : internal::DecodeUtf8(text)) {
      const std::uint8_t* rows = internal::FindGlyph(code);
      for (int row = 0; row < internal::kGlyphHeight; ++row) {
        for (int col = 0; col < internal::kGlyphWidth; ++col) {
          const bool on = rows != nullptr ? ((rows[row] >> (internal::kGlyphWidth - 1 - col)) & 1) != 0
                                          : row < 7 && (row == 0 || row == 6 || col == 0 || col == 4);
          if (on) Fill({x + col * scale, y + row * scale, scale, scale}, c);
        }
      }
      x += internal::kGlyphAdvance * scale;
    }
  }
  // Text on a white patch, for labels over the plot.
  void Label(int x, int y, const std::string& text, const Colour& c) {
    Fill({x - 2, y - 2, internal::TextWidth(text) + 4, internal::kGlyphHeight + 3}, kWhite, 0.8);
    Text(x, y, text, c);
  }
  sim::Image TakeImage() { return std::move(image_); }
  std::vector<std::string> TakeTexts() { return std::move(texts_); }

 private:
  // Liang-Barsky against the clip box grown by `grow`; false when nothing of a-b is inside.
  bool ClipSegment(Px* a, Px* b, double grow) const {
    const Px d = *b - *a;
    double t0 = 0, t1 = 1;
    const double lo[2] = {clip_.x - grow, clip_.y - grow};
    const double hi[2] = {clip_.x + clip_.width + grow, clip_.y + clip_.height + grow};
    for (int k = 0; k < 2; ++k) {
      const double p0 = (*a)[k];
      if (d[k] == 0) {
        if (p0 < lo[k] || p0 > hi[k]) return false;
        continue;
      }
      double ta = (lo[k] - p0) / d[k], tb = (hi[k] - p0) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    if (t0 > t1) return false;
    const Px start = *a + d * t0;
    *b = *a + d * t1;
    *a = start;
    return true;
  }

  sim::Image image_;
  PixelBox clip_;
  std::vector<std::string> texts_;
};

Px At(const TopdownView& v, const Eigen::Vector2d& w) { return v.ToPixel(w); }
Px At(const TopdownView& v, const Eigen::Isometry3d& T) { return v.ToPixel(T.translation().head<2>()); }
PixelBox PlotBox(const TopdownView& v) { return {v.left_px, v.top_px, v.width_px, v.height_px}; }

// The plot's pixel box of a world rectangle, clipped to the plot.
PixelBox WorldBox(const TopdownView& v, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const Px a = v.ToPixel({lo.x(), hi.y()}), b = v.ToPixel({hi.x(), lo.y()});
  const int x0 = std::max(v.left_px, ToInt(a.x())), y0 = std::max(v.top_px, ToInt(a.y()));
  const int x1 = std::min(v.left_px + v.width_px - 1, ToInt(b.x())), y1 = std::min(v.top_px + v.height_px - 1, ToInt(b.y()));
  return {x0, y0, std::max(0, x1 - x0 + 1), std::max(0, y1 - y0 + 1)};
}

// The world rectangle shown: start, route, path and goal with a 10 m margin. Values that are not
// finite or lie farther than kFarM are left out (a diverged simulation must not size the picture).
std::pair<Eigen::Vector2d, Eigen::Vector2d> Extent(const Scenario& scenario, const RunResult& r) {
  constexpr double kFarM = 1e7;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(HUGE_VAL), hi = -lo;
  auto grow = [&](const Eigen::Vector2d& p) {
    if (p.allFinite() && p.cwiseAbs().maxCoeff() < kFarM) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  };
  grow({scenario.sim.start_x_m, scenario.sim.start_y_m});
  for (const auto& p : scenario.route_m) grow(p);
  for (const auto& s : r.trajectory) grow(s.T_W_B.translation().head<2>());
  if (scenario.criteria.goal_m) {
    const double radius = std::isfinite(scenario.criteria.goal_radius_m) ? scenario.criteria.goal_radius_m : 0.0;
    grow(*scenario.criteria.goal_m - Eigen::Vector2d::Constant(radius));
    grow(*scenario.criteria.goal_m + Eigen::Vector2d::Constant(radius));
  }
  if (!lo.allFinite()) lo = hi = Eigen::Vector2d::Zero();
  return {lo - Eigen::Vector2d(10, 10), hi + Eigen::Vector2d(10, 10)};
}

std::string TickLabel(double value, double step) {
  const int digits = step >= 1 ? 0 : std::min(6, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
  std::string s = Fixed(std::abs(value) < step * 1e-6 ? 0.0 : value, digits);
  return s;
}

// Ticks at the multiples of `step` in [lo, hi] (positions filled in later).
std::vector<AxisTick> TickValues(double lo, double hi, double step) {
  std::vector<AxisTick> ticks;
  for (double k = std::ceil(lo / step); k <= std::floor(hi / step) && ticks.size() < 100; ++k) ticks.push_back({k * step, 0});
  return ticks;
}

void DrawTerrain(Raster& canvas, const TopdownView& v, const sim::Heightfield& terrain) {
  const double zmin = terrain.min_height_m(), zspan = std::max(1e-6, terrain.max_height_m() - zmin);
  const Vec3 light = Vec3(-1, 1, 2).normalized();
  for (int py = v.top_px; py < v.top_px + v.height_px; ++py) {
    for (int px = v.left_px; px < v.left_px + v.width_px; ++px) {
      const Eigen::Vector2d w = v.ToWorld({px + 0.5, py + 0.5});
      const double h = (terrain.HeightAt(w.x(), w.y()) - zmin) / zspan;
      const double shade = std::clamp(terrain.NormalAt(w.x(), w.y()).dot(light), 0.0, 1.0);
      const int g = std::clamp(static_cast<int>(150 + 60 * h + 45 * (shade - 0.8)), 0, 245);
      canvas.Set(px, py, {std::uint8_t(g), std::uint8_t(g), std::uint8_t(g + 10)});
    }
  }
}

// Footprints of every solid (dark), of roofs and other raised objects lighter; only the pixels of
// the plot are visited, so the work scales with the picture, not with the object.
void DrawObjects(Raster& canvas, const TopdownView& v, const Scenario& scenario, const sim::Heightfield& terrain) {
  for (const sim::Solid& s : sim::ResolveSolids(scenario.sim.world, terrain)) {
    const Vec3 c = s.T_W_X.translation();
    const bool elevated = c.z() - terrain.HeightAt(c.x(), c.y()) - s.half_extents.z() > 1.0;
    const double reach = s.half_extents.head<2>().norm();
    const Eigen::Isometry3d T_X_W = s.T_W_X.inverse();
    const PixelBox box = WorldBox(v, c.head<2>().array() - reach, c.head<2>().array() + reach);
    for (int py = box.y; py < box.y + box.height; ++py) {
      for (int px = box.x; px < box.x + box.width; ++px) {
        const Eigen::Vector2d w = v.ToWorld({px + 0.5, py + 0.5});
        const Vec3 p = T_X_W * Vec3(w.x(), w.y(), c.z());
        const Eigen::Vector2d q = p.head<2>().cwiseQuotient(s.half_extents.head<2>());
        const bool inside = s.shape == sim::Solid::Shape::kBox ? q.cwiseAbs().maxCoeff() <= 1.0 : q.squaredNorm() <= 1.0;
        if (inside) canvas.Set(px, py, elevated ? kRoof : kObject, elevated ? 0.45 : 0.9);
      }
    }
  }
}

// Forbidden regions: translucent, hatched and outlined.
void DrawForbidden(Raster& canvas, const TopdownView& v, const std::vector<Region>& regions) {
  for (const Region& region : regions) {
    if (!region.min_m.allFinite() && !region.max_m.allFinite()) continue;
    const PixelBox box = WorldBox(v, region.min_m, region.max_m);
    for (int py = box.y; py < box.y + box.height; ++py)
      for (int px = box.x; px < box.x + box.width; ++px) canvas.Set(px, py, kForbidden, (px + py) % 8 < 2 ? 0.8 : 0.2);
    const Px a = v.ToPixel({region.min_m.x(), region.max_m.y()}), b = v.ToPixel({region.max_m.x(), region.min_m.y()});
    canvas.Line(a, {b.x(), a.y()}, 0, kForbidden);
    canvas.Line({b.x(), a.y()}, b, 0, kForbidden);
    canvas.Line(b, {a.x(), b.y()}, 0, kForbidden);
    canvas.Line({a.x(), b.y()}, a, 0, kForbidden);
  }
}

// A pose: a triangle pointing along the heading.
void DrawPose(Raster& canvas, const Px& at, double yaw_rad, const Colour& fill) {
  const Px ahead(std::cos(yaw_rad), -std::sin(yaw_rad)), side(-ahead.y(), ahead.x());
  canvas.Polygon({at + 9 * ahead, at - 5 * ahead + 5 * side, at - 5 * ahead - 5 * side}, fill, kInk);
}

void DrawStallMark(Raster& canvas, const Px& at) {
  canvas.Polygon({at + Px(-4, -4), at + Px(4, -4), at + Px(4, 4), at + Px(-4, 4)}, kStall, kInk);
}
void DrawRockingMark(Raster& canvas, const Px& at) {
  canvas.Polygon({at + Px(0, -6), at + Px(6, 0), at + Px(0, 6), at + Px(-6, 0)}, kRocking, kInk);
}

// Map points, route, path driven, goal, start and end poses.
void DrawRun(Raster& canvas, const TopdownView& v, const Scenario& scenario, const RunResult& r) {
  for (const MapPoint& p : r.map_points) {
    const Px q = At(v, Eigen::Vector2d(p.position_W.head<2>()));
    if (q.allFinite()) canvas.Set(ToInt(q.x()), ToInt(q.y()), p.traversable ? kTraversable : kNotTraversable, 0.45);
  }
  if (scenario.criteria.goal_m) {
    const Px g = At(v, *scenario.criteria.goal_m);
    const double radius = scenario.criteria.goal_radius_m * v.px_per_m;
    canvas.Disc(g, radius, kGoal, 0.3);
    canvas.Disc(g, radius, kGoal, 1.0, radius - 2.0);
    canvas.Line(g - Px(4, 0), g + Px(4, 0), 0, kGoal);
    canvas.Line(g - Px(0, 4), g + Px(0, 4), 0, kGoal);
  }
  for (std::size_t i = 0; i + 1 < scenario.route_m.size(); ++i) {
    canvas.Line(At(v, scenario.route_m[i]), At(v, scenario.route_m[i + 1]), 0, kRoute);
  }
  for (std::size_t i = 0; i + 1 < r.trajectory.size(); ++i) {
    canvas.Line(At(v, r.trajectory[i].T_W_B), At(v, r.trajectory[i + 1].T_W_B), 1, kPath);
  }
  DrawPose(canvas, At(v, Eigen::Vector2d(scenario.sim.start_x_m, scenario.sim.start_y_m)), scenario.sim.start_yaw_rad, kStart);
  if (!r.trajectory.empty()) DrawPose(canvas, At(v, r.trajectory.back().T_W_B), HeadingRad(r.trajectory.back().T_W_B), kEnd);
}

// Each spell's mark, and its start time beside it; a label moves down until it overlaps no other.
void DrawSpells(Raster& canvas, const TopdownView& v, const std::vector<Spell>& spells) {
  std::vector<PixelBox> placed;
  for (const Spell& s : spells) {
    const Px at = At(v, s.at_m);
    if (s.kind == "stall") DrawStallMark(canvas, at);
    else DrawRockingMark(canvas, at);
  }
  for (const Spell& s : spells) {
    const Px at = At(v, s.at_m);
    const std::string text = "t=" + Fixed(s.start_s, 1) + " s";
    PixelBox box{ToInt(at.x()) + 9, ToInt(at.y()) - 4, internal::TextWidth(text), internal::kGlyphHeight};
    if (box.x + box.width > v.left_px + v.width_px) box.x = ToInt(at.x()) - 9 - box.width;  // keep it on the plot
    const auto overlaps = [&](const PixelBox& b) {
      return std::any_of(placed.begin(), placed.end(), [&](const PixelBox& o) {
        return b.x < o.x + o.width + 3 && o.x < b.x + b.width + 3 && b.y < o.y + o.height + 3 && o.y < b.y + b.height + 3;
      });
    };
    for (int tries = 0; tries < 20 && overlaps(box); ++tries) box.y += internal::kLineHeight + 2;
    placed.push_back(box);
    canvas.Label(box.x, box.y, text, kInk);
  }
}

// Faint lines at the ticks, drawn over the terrain and under everything else.
void DrawGrid(Raster& canvas, const TopdownFigure& f) {
  const TopdownView& v = f.view;
  for (const AxisTick& t : f.x_ticks) canvas.Fill({t.pixel, v.top_px, 1, v.height_px}, kInk, 0.12);
  for (const AxisTick& t : f.y_ticks) canvas.Fill({v.left_px, t.pixel, v.width_px, 1}, kInk, 0.12);
}

// Frame, ticks and tick labels, the axes' names (the grid is under the plot's marks: DrawGrid).
void DrawAxes(Raster& canvas, const TopdownFigure& f) {
  const TopdownView& v = f.view;
  const int bottom = v.top_px + v.height_px;
  canvas.Frame({v.left_px - 1, v.top_px - 1, v.width_px + 2, v.height_px + 2}, kInk);
  for (const AxisTick& t : f.x_ticks) {
    canvas.Fill({t.pixel, bottom + 1, 1, kTick}, kInk);
    const std::string label = TickLabel(t.value_m, f.tick_step_m);
    canvas.Text(t.pixel - internal::TextWidth(label) / 2, bottom + kTick + 4, label, kInk);
  }
  for (const AxisTick& t : f.y_ticks) {
    canvas.Fill({v.left_px - 1 - kTick, t.pixel, kTick, 1}, kInk);
    const std::string label = TickLabel(t.value_m, f.tick_step_m);
    canvas.Text(v.left_px - kTick - 4 - internal::TextWidth(label), t.pixel - 3, label, kInk);
  }
  const std::string x_name = "x [m] (east)", y_name = "y [m] (north)";
  canvas.Text(v.left_px + (v.width_px - internal::TextWidth(x_name)) / 2, bottom + kTick + 4 + internal::kLineHeight + 6,
              x_name, kInk);
  canvas.Text(std::max(kMargin, v.left_px - internal::TextWidth(y_name) / 2), v.top_px - 18, y_name, kInk);
}

// `text` cut to at most `width` pixels at `scale`, "..." marking a cut.
std::string Fit(const std::string& text, int width, int scale) {
  if (internal::TextWidth(text, scale) <= width) return text;
  const std::size_t keep = static_cast<std::size_t>(std::max(0, width / (internal::kGlyphAdvance * scale) - 3));
  return text.substr(0, keep) + "...";
}

void DrawTitle(Raster& canvas, const Scenario& scenario, const RunResult& r, int width) {
  const Diagnosis d = Diagnose(r);
  std::string title = (scenario.name.empty() ? r.scenario : scenario.name) + "   seed " + std::to_string(r.seed) + "   " +
                      (r.passed ? "PASS" : "FAIL");
  if (!d.verdict.empty()) title += " (" + d.verdict + ")";
  title += "   " + Fixed(r.sim_time_s, 1) + " s simulated";
  const int scale = internal::TextWidth(title, 2) <= width ? 2 : 1;
  canvas.Text(kMargin, 8, Fit(title, width, scale), kInk, scale);
  std::string sub = r.end_reason.empty() ? "" : r.end_reason + "; ";
  sub += "driven " + Fixed(r.distance_m, 1) + " m, route progress " + Fixed(r.route_progress_m, 1) + " / " +
         Fixed(r.route_length_m, 1) + " m" + (r.map_backend.empty() ? "" : ", map " + r.map_backend);
  canvas.Text(kMargin, 32, Fit(sub, width, 1), kGreyInk);
}


// The legend: a sample of each mark and its name, and a scale bar under them.
enum class Sample { kLine, kThickLine, kPose, kCircle, kArea, kDots, kHatch, kSquare, kDiamond };
struct LegendLine {
  std::string label;
  Colour colour;
  Sample sample;
};

std::vector<LegendLine> LegendLines(const Scenario& scenario) {
  const std::string goal = scenario.criteria.goal_m
                               ? "goal (radius " + Fixed(scenario.criteria.goal_radius_m, 1) + " m)"
                               : "goal (none set)";
  return {{"route", kRoute, Sample::kLine},
          {"path driven", kPath, Sample::kThickLine},
          {"start pose", kStart, Sample::kPose},
          {"end pose", kEnd, Sample::kPose},
          {goal, kGoal, Sample::kCircle},
          {"objects", kObject, Sample::kArea},
          {"roofs, overhangs", kRoof, Sample::kArea},
          {"map: traversable", kTraversable, Sample::kDots},
          {"map: not traversable", kNotTraversable, Sample::kDots},
          {"forbidden region", kForbidden, Sample::kHatch},
          {"stall (t=its start)", kStall, Sample::kSquare},
          {"rocking (t=its start)", kRocking, Sample::kDiamond}};
}

void DrawSample(Raster& canvas, const PixelBox& b, const LegendLine& line) {
  const Px mid(b.x + b.width / 2.0, b.y + b.height / 2.0);
  switch (line.sample) {
    case Sample::kLine: canvas.Fill({b.x, b.y + b.height / 2, b.width, 1}, line.colour); break;
    case Sample::kThickLine: canvas.Fill({b.x, b.y + b.height / 2 - 1, b.width, 3}, line.colour); break;
    case Sample::kPose: DrawPose(canvas, mid, 0.0, line.colour); break;
    case Sample::kCircle:
      canvas.Disc(mid, b.height / 2.0 + 1, line.colour, 0.3);
      canvas.Disc(mid, b.height / 2.0 + 1, line.colour, 1.0, b.height / 2.0 - 1);
      break;
    case Sample::kArea:
      canvas.Fill(b, line.colour, line.colour == kRoof ? 0.45 : 0.9);
      canvas.Frame(b, line.colour);
      break;
    case Sample::kDots:
      for (int y = b.y + 1; y < b.y + b.height; y += 3)
        for (int x = b.x + 1 + (y % 2); x < b.x + b.width; x += 3) canvas.Fill({x, y, 2, 2}, line.colour);
      break;
    case Sample::kHatch:
      for (int y = b.y; y < b.y + b.height; ++y)
        for (int x = b.x; x < b.x + b.width; ++x) canvas.Set(x, y, kForbidden, (x + y) % 8 < 2 ? 0.8 : 0.2);
      canvas.Frame(b, kForbidden);
      break;
    case Sample::kSquare: DrawStallMark(canvas, mid); break;
    case Sample::kDiamond: DrawRockingMark(canvas, mid); break;
  }
}

// The largest 1, 2 or 5 times a power of ten not above `limit` (> 0).
double RoundBelow(double limit) {
  const double power = std::pow(10.0, std::floor(std::log10(limit)));
  return limit >= 5 * power ? 5 * power : limit >= 2 * power ? 2 * power : power;
}

// The legend's size, with its top-left corner at (x, y).
PixelBox LegendBox(const std::vector<LegendLine>& lines, int x, int y) {
  int label_w = internal::TextWidth("scale bar: 500 m") - kSampleW - 8;
  for (const LegendLine& line : lines) label_w = std::max(label_w, internal::TextWidth(line.label));
  const int rows = static_cast<int>(lines.size()) + 2;
  return {x, y, 8 + kSampleW + 8 + label_w + 8, 8 + rows * kRow + 4};
}

void DrawLegend(Raster& canvas, TopdownFigure& f, const std::vector<LegendLine>& lines) {
  const PixelBox& box = f.legend;
  canvas.Fill(box, {252, 252, 248});
  canvas.Frame(box, kGreyInk);
  int y = box.y + 8;
  for (const LegendLine& line : lines) {
    const PixelBox sample{box.x + 8, y + 1, kSampleW, 10};
    DrawSample(canvas, sample, line);
    canvas.Text(sample.x + kSampleW + 8, y + 2, line.label, kInk);
    f.legend_entries.push_back({line.label, line.colour, sample});
    y += kRow;
  }
  // The scale bar: a round length no wider than the legend.
  const double bar_m = RoundBelow(std::max(1e-9, (box.width - 24) / f.view.px_per_m));
  const int bar_px = std::max(1, ToInt(bar_m * f.view.px_per_m));
  y += kRow / 2;
  canvas.Text(box.x + 8, y, "scale bar: " + TickLabel(bar_m, bar_m) + " m", kInk);
  y += kRow;
  canvas.Fill({box.x + 8, y + 2, bar_px, 4}, kInk);
  canvas.Fill({box.x + 8 + bar_px / 2, y + 3, bar_px - bar_px / 2 - 1, 2}, kWhite);
  canvas.Fill({box.x + 8, y, 1, 8}, kInk);
  canvas.Fill({box.x + 8 + bar_px - 1, y, 1, 8}, kInk);
}

// The plot's place and scale, and the ticks: at most 2000 pixels on a side, 20 per metre at most.
void Layout(TopdownFigure& f, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  const double extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const double px_per_m = std::min(20.0, std::max(1000.0 / extent, std::min(2.0, 2000.0 / extent)));
  f.tick_step_m = TickStep(extent);
  f.x_ticks = TickValues(lo.x(), hi.x(), f.tick_step_m);
  f.y_ticks = TickValues(lo.y(), hi.y(), f.tick_step_m);
  int label_w = 0;
  for (const AxisTick& t : f.y_ticks) label_w = std::max(label_w, internal::TextWidth(TickLabel(t.value_m, f.tick_step_m)));
  TopdownView& v = f.view;
  v.x0_m = lo.x();
  v.y1_m = hi.y();
  v.px_per_m = px_per_m;
  v.left_px = std::max(kMargin + label_w + kTick + 6, kMargin + internal::TextWidth("y [m] (north)") / 2);
  v.top_px = kTop;
  v.width_px = std::clamp(static_cast<int>(std::ceil((hi.x() - lo.x()) * px_per_m)), 1, 2000);
  v.height_px = std::clamp(static_cast<int>(std::ceil((hi.y() - lo.y()) * px_per_m)), 1, 2000);
  for (AxisTick& t : f.x_ticks) t.pixel = ToInt(v.ToPixel({t.value_m, 0.0}).x());
  for (AxisTick& t : f.y_ticks) t.pixel = ToInt(v.ToPixel({0.0, t.value_m}).y());
}

}  // namespace

TopdownFigure DrawTopdown(const Scenario& scenario, const RunResult& r) {
  TopdownFigure f;
  const auto [lo, hi] = Extent(scenario, r);
  Layout(f, lo, hi);
  const TopdownView& v = f.view;
  const std::vector<LegendLine> lines = LegendLines(scenario);
  f.legend = LegendBox(lines, v.left_px + v.width_px + kLegendGap, v.top_px);
  const int width = f.legend.x + f.legend.width + kMargin;
  const int height = std::max(v.top_px + v.height_px + kBottom, f.legend.y + f.legend.height + kMargin);
  Raster canvas(width, height);

  canvas.Clip(PlotBox(v));
  const sim::Heightfield terrain = sim::MakeHeightfield(scenario.sim.world.terrain);
  DrawTerrain(canvas, v, terrain);
  DrawGrid(canvas, f);
  DrawObjects(canvas, v, scenario, terrain);
  DrawForbidden(canvas, v, scenario.criteria.forbidden);
  DrawRun(canvas, v, scenario, r);
  f.spells = FindSpells(r);
  if (f.spells.size() > kMaxSpells) f.spells.resize(kMaxSpells);
  DrawSpells(canvas, v, f.spells);
  canvas.Unclip();

  DrawAxes(canvas, f);
  DrawTitle(canvas, scenario, r, width - 2 * kMargin);
  DrawLegend(canvas, f, lines);
  f.image = canvas.TakeImage();
  f.texts = canvas.TakeTexts();
  return f;
}

void WriteTopdownPng(const Scenario& scenario, const RunResult& result, const std::string& path) {
  sim::WritePng(DrawTopdown(scenario, result).image, path);
}

double TickStep(double extent_m) {
  if (!std::isfinite(extent_m) || extent_m <= 0) return 1.0;
  double power = std::pow(10.0, std::floor(std::log10(extent_m / 8)));
  for (;; power *= 10) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (extent_m / (m * power) <= 8 + 1e-9) return m * power;
    }
  }
}

}  // namespace ovpc::scenarios
