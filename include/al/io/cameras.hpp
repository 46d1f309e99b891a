// Camera files: INRIA cameras.json, COLMAP text (cameras.txt + images.txt, PINHOLE /
// SIMPLE_PINHOLE), and al-refine's plain JSON list (RASTERIZER.md §10.2-10.3, SPEC §3).
#pragma once
#include <string>
#include <vector>

#include "al/io/camera.hpp"

namespace al {

struct CameraLoadResult {
  std::vector<Camera> cameras;
  std::vector<std::string> warnings;  // e.g. principal point off-centre (ignored by INRIA-exact rendering)
  std::string format;                 // "inria", "colmap", "list"
};

// path: a .json file (INRIA list or plain list, told apart by keys), a COLMAP folder holding
// cameras.txt + images.txt, or either of those two files. Throws al::Error naming the file.
CameraLoadResult ReadCameras(const std::string& path);

// Writes the plain JSON list {name, W2C (4x4 rows), fx, fy, cx, cy, width, height} atomically.
void WriteCameraList(const std::string& path, const std::vector<Camera>& cameras);

// Writes INRIA cameras.json (rotation = camera-to-world, position = centre) atomically.
void WriteInriaCameras(const std::string& path, const std::vector<Camera>& cameras);

// Selects views by comma-separated names or "all"; throws al::Error for unknown names.
std::vector<Camera> SelectViews(const std::vector<Camera>& cameras, const std::string& views);

}  // namespace al
