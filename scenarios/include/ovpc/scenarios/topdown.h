// The top-down figure of a run (topdown.png): the terrain, objects, forbidden regions, the robot's
// map points, the route and the path driven, the start, the goal, the end pose and where the
// vehicle stalled or rocked, with axes in metres, a title, a legend and a scale bar. Text is drawn
// with the project's own bitmap font; the same run gives the same pixels.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ovpc/scenarios/diagnosis.h"
#include "ovpc/scenarios/run_result.h"
#include "ovpc/scenarios/scenario.h"
#include "ovpc/sim/image.h"

namespace ovpc::scenarios {

/// Where the world lies in the picture. World: x east, y north, metres. Picture: x right, y down,
/// pixels; pixel (i, j) covers [i, i+1) x [j, j+1), so its centre is (i + 0.5, j + 0.5).
struct TopdownView {
  double x0_m = 0.0;  ///< world x at the plot's left edge
  double y1_m = 0.0;  ///< world y at the plot's top edge
  double px_per_m = 1.0;
  int left_px = 0, top_px = 0;        ///< the plot's top-left corner in the picture
  int width_px = 0, height_px = 0;    ///< the plot's size

  Eigen::Vector2d ToPixel(const Eigen::Vector2d& world_m) const {
    return {left_px + (world_m.x() - x0_m) * px_per_m, top_px + (y1_m - world_m.y()) * px_per_m};
  }
  Eigen::Vector2d ToWorld(const Eigen::Vector2d& pixel) const {
    return {x0_m + (pixel.x() - left_px) / px_per_m, y1_m - (pixel.y() - top_px) / px_per_m};
  }
};

/// A rectangle of pixels: columns [x, x + width), rows [y, y + height).
struct PixelBox {
  int x = 0, y = 0, width = 0, height = 0;
  bool Contains(int px, int py) const { return px >= x && py >= y && px < x + width && py < y + height; }
};

/// An axis tick: its value in metres and its pixel column (x axis) or row (y axis).
struct AxisTick {
  double value_m = 0.0;
  int pixel = 0;
};

/// A legend line: the mark's name, its key colour and where its sample is drawn.
struct LegendEntry {
  std::string label;
  std::array<std::uint8_t, 3> colour{};
  PixelBox sample;
};

struct TopdownFigure {
  sim::Image image;
  TopdownView view;
  double tick_step_m = 1.0;
  std::vector<AxisTick> x_ticks, y_ticks;
  PixelBox legend;                    ///< the legend box, scale bar included
  std::vector<LegendEntry> legend_entries;
  std::vector<Spell> spells;          ///< the stalls and rocking spells marked (FindSpells)
  std::vector<std::string> texts;     ///< every text drawn, in drawing order
};

/// The round tick step for a plot `extent_m` wide: 1, 2 or 5 times a power of ten, the smallest
/// that gives at most 8 steps across it (1 m for a non-finite or non-positive extent).
double TickStep(double extent_m);

/// Draws the figure of `result` of `scenario`. Non-finite poses and points are left out, and the
/// extent ignores places farther than 10,000 km; the plot is at most 2000 pixels on a side.
TopdownFigure DrawTopdown(const Scenario& scenario, const RunResult& result);

}  // namespace ovpc::scenarios
