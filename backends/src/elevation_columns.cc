#include "ovpc/backends/elevation_columns.h"

#include <algorithm>

namespace ovpc::backends {

ColumnGrid ElevationColumns(const baselines::ElevationMap& map) {
  const double res = map.config().resolution_m;
  const int cells = map.cells_per_side();
  const Eigen::Vector2d corner = map.centre() - Eigen::Vector2d::Constant(0.5 * cells * res);
  const auto cell_at = [&](int col, int row) {
    return map.FindCell(corner + Eigen::Vector2d((col + 0.5) * res, (row + 0.5) * res));
  };
  // The grid covers the non-empty cells.
  int lo_c = cells, hi_c = -1, lo_r = cells, hi_r = -1;
  for (int row = 0; row < cells; ++row) {
    for (int col = 0; col < cells; ++col) {
      const baselines::ElevationMap::Cell* cell = cell_at(col, row);
      if (cell == nullptr || cell->empty()) continue;
      lo_c = std::min(lo_c, col), hi_c = std::max(hi_c, col), lo_r = std::min(lo_r, row), hi_r = std::max(hi_r, row);
    }
  }
  ColumnGrid grid;
  grid.solid_below = true;
  if (hi_c < 0) {
    grid.Reset(res, 0.0, 0.0, 0, 0);
    return grid;
  }
  grid.Reset(res, corner.x() + lo_c * res, corner.y() + lo_r * res, hi_c - lo_c + 1, hi_r - lo_r + 1);
  for (int iy = 0; iy < grid.ny; ++iy) {
    for (int ix = 0; ix < grid.nx; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * grid.nx + ix;
      const baselines::ElevationMap::Cell* cell = cell_at(lo_c + ix, lo_r + iy);
      if (cell != nullptr && !cell->empty()) {
        grid.sample_ground.push_back(static_cast<std::int32_t>(grid.ground_z.size()));
        grid.ground_z.push_back(cell->height_m);
        grid.sample_z.push_back(cell->height_m);
      }
      grid.ground_begin[c + 1] = static_cast<std::uint32_t>(grid.ground_z.size());
      grid.sample_begin[c + 1] = static_cast<std::uint32_t>(grid.sample_z.size());
    }
  }
  return grid;
}

}  // namespace ovpc::backends
