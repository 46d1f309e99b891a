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
// View names are made safe and unique (MakeViewNamesSafe), with a warning for each change.
CameraLoadResult ReadCameras(const std::string& path);

// A view name as a file-name part: '/', '\\', ':' and control characters (NUL included) become
// '_'; an empty, "." or ".." name becomes "view"; at most 160 bytes (outputs add suffixes).
std::string SafeFileName(std::string name);
// Makes every name safe (SafeFileName) and unique: a repeat gets "_2", "_3", ... so that views
// never overwrite each other's outputs. Returns one warning per renamed view.
std::vector<std::string> MakeViewNamesSafe(std::vector<Camera>& cameras);

// In-memory parsers behind ReadCameras (for fuzzing and embedding); `*_name` prefixes errors.
CameraLoadResult ParseCamerasJson(const std::string& text, const std::string& name);
CameraLoadResult ParseColmapText(const std::string& cameras_text, const std::string& images_text,
                                 const std::string& cameras_name = "cameras.txt",
                                 const std::string& images_name = "images.txt");

// Formats:
// * INRIA cameras.json: [{img_name, width, height, fx, fy, position, rotation}], rotation = camera-
//   to-world rows, position = centre: R = rotationᵀ, t = −rotationᵀ·position, cx = W/2, cy = H/2.
// * COLMAP text: cameras.txt PINHOLE (fx fy cx cy) / SIMPLE_PINHOLE (f cx cy) (other models: error,
//   undistort first); images.txt two lines per image, quaternion w-first world->camera; name = the
//   file stem of NAME. COLMAP's cx, cy use the same pixel-centre convention as Camera.
// * Plain list: [{name, W2C: 4 rows of 4 (world->camera, last row 0 0 0 1), fx, fy, cx, cy, width,
//   height}]; cx, cy in the "pixel centres at j + 0.5" convention (cx = W/2 is centred); optional,
//   default centred. A JSON object {"cameras": [...]} is accepted too.
// Validation (error naming the entry): positive integer size, positive finite focal, finite values,
// proper rotation (|RᵀR − I| <= 1e-3, det > 0). Warnings: principal point more than 0.5 px off the
// centre (INRIA-exact rendering ignores it), duplicate names.

// Writes the plain JSON list {name, W2C (4x4 rows), fx, fy, cx, cy, width, height} atomically.
void WriteCameraList(const std::string& path, const std::vector<Camera>& cameras);

// Writes INRIA cameras.json (rotation = camera-to-world, position = centre) atomically.
void WriteInriaCameras(const std::string& path, const std::vector<Camera>& cameras);

// Selects views by comma-separated names (in the given order, repeats dropped) or "all" / empty;
// throws al::Error listing a few known names for an unknown name.
std::vector<Camera> SelectViews(const std::vector<Camera>& cameras, const std::string& views);

}  // namespace al
