#include "scan_smoothing.hpp"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace dmgplace::tools::detail {

namespace {

std::shared_ptr<pcl::KdTreeFLANN<pcl::PointXYZ>> tree_of(const std::vector<Eigen::Vector3d>& points) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  auto tree = std::make_shared<pcl::KdTreeFLANN<pcl::PointXYZ>>();
  tree->setInputCloud(cloud);
  return tree;
}

}  // namespace

double median_point_spacing(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return 0;
  const auto tree = tree_of(points);
  std::vector<double> d;
  std::vector<int> idx(2);
  std::vector<float> sq(2);
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 2000);  // a sample is enough for a median
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (tree->nearestKSearch(int(i), 2, idx, sq) == 2) d.push_back(std::sqrt(double(sq[1])));
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

void agree_with_neighbours(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>& normals,
                           double radius) {
  const auto tree = tree_of(points);
  std::vector<int> idx;
  std::vector<float> sq;
  for (int sweep = 0; sweep < 2; ++sweep) {
    const auto before = normals;
    for (std::size_t i = 0; i < points.size(); ++i) {
      tree->radiusSearch(int(i), radius, idx, sq);
      double vote = 0;
      for (int j : idx)
        if (std::size_t(j) != i) vote += before[i].dot(before[std::size_t(j)]);
      if (vote < 0) normals[i] = -before[i];
    }
  }
}

void smooth_points(const std::vector<Eigen::Vector3d>& points, double radius, std::vector<Eigen::Vector3d>& smoothed,
                   std::vector<Eigen::Vector3d>& normals) {
  const auto tree = tree_of(points);
  smoothed.assign(points.size(), Eigen::Vector3d::Zero());
  normals.assign(points.size(), Eigen::Vector3d::Zero());
  const double h2 = radius * radius / 4;  // Gaussian weight exp(-d^2 / h2): h = radius / 2
  std::vector<int> idx;
  std::vector<float> sq;
  for (std::size_t i = 0; i < points.size(); ++i) {
    smoothed[i] = points[i];
    tree->radiusSearch(int(i), radius, idx, sq);
    if (idx.size() < 3) continue;
    // Weighted plane: centroid and the covariance's least eigenvector.
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double wsum = 0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const double w = std::exp(-double(sq[k]) / h2);
      mean += w * points[std::size_t(idx[k])], wsum += w;
    }
    mean /= wsum;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const Eigen::Vector3d d = points[std::size_t(idx[k])] - mean;
      cov += std::exp(-double(sq[k]) / h2) * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d n = es.eigenvectors().col(0), u = es.eigenvectors().col(2), v = es.eigenvectors().col(1);
    normals[i] = n;
    if (idx.size() < 6) continue;
    // Quadric height over the plane: h(a, b) = c0 + c1 a + c2 b + c3 a^2 + c4 a b + c5 b^2.
    Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
    const Eigen::Vector3d origin = mean + n * n.dot(points[i] - mean);  // the point's foot on the plane
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const Eigen::Vector3d d = points[std::size_t(idx[k])] - origin;
      const double a = d.dot(u), b = d.dot(v), w = std::exp(-double(sq[k]) / h2);
      Eigen::Matrix<double, 6, 1> row;
      row << 1, a, b, a * a, a * b, b * b;
      ata += w * row * row.transpose();
      atb += w * row * d.dot(n);
    }
    const Eigen::Matrix<double, 6, 1> c = ata.ldlt().solve(atb);
    if (!c.allFinite()) continue;
    smoothed[i] = origin + c[0] * n;                      // the surface above the foot point
    normals[i] = (n - c[1] * u - c[2] * v).normalized();  // gradient of the height field at (0, 0)
  }
}

}  // namespace dmgplace::tools::detail
