// The 2.5D elevation backend's map: baselines::ElevationMap's cells read into columns.
#pragma once

#include "ovpc/backends/column_map.h"
#include "ovpc/baselines/elevation_map.h"

namespace ovpc::backends {

/// One column per non-empty cell of `map`: its height is both the column's one ground candidate and
/// the top of a solid column (ColumnGrid::solid_below). One height per cell, so a roof over a cell
/// is that cell's height: the ground under it is gone, and the roof is a surface at the roof's
/// height, walled in by steps (the 2.5D limitation; not special-cased).
ColumnGrid ElevationColumns(const baselines::ElevationMap& map);

}  // namespace ovpc::backends
