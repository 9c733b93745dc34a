// Reading and writing point clouds and meshes in formats other tools open (PLY, PCD, KITTI .bin,
// .xyz). No dependency beyond the standard library.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "ovpc/core/free_space_mesh.h"
#include "ovpc/core/types.h"

namespace ovpc {

class TraversabilityCloud;

/// Any failure to read or write a file. what() is one line that names the file and the reason.
class CloudIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class CloudFormat { kAuto, kPly, kPcd, kKittiBin, kXyz };

/// Format from the file extension (.ply, .pcd, .bin, .xyz/.txt); kAuto if unknown.
CloudFormat FormatFromExtension(const std::string& path);

/// Reads x, y, z of every point. Supports PLY (ascii, binary little and big endian; any vertex
/// property layout with float/double/int x, y, z), PCD (ascii and binary; binary_compressed is
/// reported as unsupported), .bin with `bin_fields` float32 fields per record (4: KITTI's x, y, z,
/// intensity; 5: nuScenes' x, y, z, intensity, ring; a file that does not look like LiDAR points in
/// that layout is refused) and .xyz text (x y z per line, extra columns ignored, '#' comments).
/// Non-finite values are returned as they are (the mapper drops and counts them). Only regular
/// files of at most 2 GiB are read.
/// @throws CloudIoError for a missing/unreadable file, an unknown or malformed format.
Points ReadCloud(const std::string& path, CloudFormat format = CloudFormat::kAuto, int bin_fields = 4);

/// The same on the bytes of a file already in memory (tests, fuzzing): `name` stands for the file in
/// messages and gives the format when `format` is kAuto.
/// @throws CloudIoError for an unknown or malformed format.
Points ParseCloud(const std::string& bytes, CloudFormat format, const std::string& name, int bin_fields = 4);

/// The writers below write PATH.partial and rename it to PATH: PATH is whole or not written (an
/// earlier PATH stays as it was); a failure removes PATH.partial and throws CloudIoError.

/// Binary little-endian PLY with float x, y, z.
void WriteCloudPly(const std::string& path, const Points& points);

/// PLY mesh: vertices with float x, y, z, nx, ny, nz (vertex normals; zero for the viewpoint
/// vertex), faces with a uchar red, green, blue colour (green traversable, red not).
/// @pre vertex_normals.size() >= mesh.num_visible(); the mesh is classified.
void WriteMeshPly(const std::string& path, const FreeSpaceMesh& mesh, const std::vector<Vec3>& vertex_normals);

/// The planner's map as PLY: x, y, z, nx, ny, nz (float) and uchar traversable.
void WriteTraversabilityCloudPly(const std::string& path, const TraversabilityCloud& cloud);

}  // namespace ovpc
