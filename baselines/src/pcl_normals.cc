#include "ovpc/baselines/pcl_normals.h"

#include <cmath>
#include <stdexcept>

#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

namespace ovpc::baselines {

PcaNormals EstimatePclNormals(const Points& points, const Vec3& viewpoint,
                              const PcaNormalsConfig& config) {
  config.Validate();
  if (config.min_neighbours != 3) {
    throw std::invalid_argument("EstimatePclNormals: PCL needs min_neighbours == 3");
  }
  if (!viewpoint.allFinite()) {
    throw std::invalid_argument("EstimatePclNormals: the viewpoint is not finite");
  }
  PcaNormals result;
  result.normals.assign(points.size(), Vec3::Zero());
  if (points.empty()) return result;

  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  bool dense = true;
  for (const Vec3& p : points) {
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                   static_cast<float>(p.z())));
    dense = dense && p.allFinite();
  }
  cloud->is_dense = dense;

  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(cloud);
  estimation.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  estimation.setRadiusSearch(config.radius_m);
  estimation.setViewPoint(static_cast<float>(viewpoint.x()), static_cast<float>(viewpoint.y()),
                          static_cast<float>(viewpoint.z()));
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  if (normals.size() != points.size()) {
    throw std::runtime_error("EstimatePclNormals: PCL returned a cloud of another size");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const pcl::Normal& n = normals[i];
    const Vec3 normal(n.normal_x, n.normal_y, n.normal_z);
    if (!normal.allFinite() || normal.isZero(0.0)) {
      ++result.num_without_normal;
      continue;
    }
    result.normals[i] = normal.normalized();
  }
  return result;
}

}  // namespace ovpc::baselines
