// A pinhole camera in the INRIA/OpenCV convention: x right, y down, z forward;
// X_cam = R * X_world + t. Pixel centres are integers; the principal point used by the
// INRIA-exact renderer is ((W-1)/2, (H-1)/2) and cx, cy are kept only for reporting.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

namespace al {

struct Camera {
  std::string name;  // image stem, used to join masks to views
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0;
  double cx = 0, cy = 0;  // in the "pixel centres at j + 0.5" convention (cx = W/2 is centred)
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      // world -> camera translation

  Eigen::Vector3d Centre() const { return -R.transpose() * t; }
  double TanFovX() const { return width / (2.0 * fx); }
  double TanFovY() const { return height / (2.0 * fy); }
};

}  // namespace al
