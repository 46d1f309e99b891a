// Camera files (RASTERIZER.md §10.2-10.3): INRIA cameras.json, COLMAP text, plain JSON list.
#include "al/io/cameras.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string ReadText(const std::string& path) {
  return ReadInputFile(path, std::uint64_t(1) << 30);
}

double Num(const json& e, const char* key, const std::string& path, const std::string& where) {
  auto it = e.find(key);
  if (it == e.end()) throw FileError(path, where + ": missing '" + key + "'");
  if (!it->is_number()) throw FileError(path, where + ": '" + key + "' is not a number");
  return it->get<double>();
}

int Size(const json& e, const char* key, const std::string& path, const std::string& where) {
  const double v = Num(e, key, path, where);
  if (!(v >= 1 && v <= 1e6) || v != std::floor(v))
    throw FileError(path, where + ": '" + key + "' must be a positive integer");
  return static_cast<int>(v);
}

// Rows of a nested list, each of `cols` numbers.
Eigen::MatrixXd Matrix(const json& e, const char* key, int rows, int cols, const std::string& path,
                       const std::string& where) {
  auto it = e.find(key);
  if (it == e.end()) throw FileError(path, where + ": missing '" + key + "'");
  const std::string bad = where + ": '" + key + "' must be a list of " + std::to_string(rows) + " rows of " +
                          std::to_string(cols) + " numbers";
  Eigen::MatrixXd m(rows, cols);
  if (rows == 1) {
    if (!it->is_array() || it->size() != std::size_t(cols)) throw FileError(path, bad);
    for (int c = 0; c < cols; ++c) {
      if (!(*it)[c].is_number()) throw FileError(path, bad);
      m(0, c) = (*it)[c].get<double>();
    }
    return m;
  }
  if (!it->is_array() || it->size() != std::size_t(rows)) throw FileError(path, bad);
  for (int r = 0; r < rows; ++r) {
    const json& row = (*it)[r];
    if (!row.is_array() || row.size() != std::size_t(cols)) throw FileError(path, bad);
    for (int c = 0; c < cols; ++c) {
      if (!row[c].is_number()) throw FileError(path, bad);
      m(r, c) = row[c].get<double>();
    }
  }
  return m;
}

// Shared checks: finite numbers, positive focal, proper orthonormal rotation.
void Validate(const Camera& c, const std::string& path, const std::string& where) {
  if (!std::isfinite(c.fx) || !std::isfinite(c.fy) || c.fx <= 0 || c.fy <= 0)
    throw FileError(path, where + ": focal lengths must be positive and finite");
  if (!std::isfinite(c.cx) || !std::isfinite(c.cy)) throw FileError(path, where + ": principal point is not finite");
  if (!c.R.allFinite() || !c.t.allFinite()) throw FileError(path, where + ": pose has non-finite values");
  const double err = (c.R.transpose() * c.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-3) throw FileError(path, where + ": rotation is not orthonormal (max |RᵀR − I| = " + std::to_string(err) + ")");
  if (c.R.determinant() < 0) throw FileError(path, where + ": rotation is a reflection (determinant < 0)");
}

void WarnPrincipalPoint(const Camera& c, std::vector<std::string>& warnings) {
  if (std::abs(c.cx - c.width / 2.0) > 0.5 || std::abs(c.cy - c.height / 2.0) > 0.5) {
    std::ostringstream s;
    s << "camera '" << c.name << "': principal point (" << c.cx << ", " << c.cy << ") is off the image centre ("
      << c.width / 2.0 << ", " << c.height / 2.0 << "); INRIA-exact rendering ignores it";
    warnings.push_back(s.str());
  }
}

std::string NameOf(const json& e, const char* key, const std::string& path, const std::string& where) {
  auto it = e.find(key);
  if (it == e.end()) throw FileError(path, where + ": missing '" + key + "'");
  if (it->is_string()) return it->get<std::string>();
  if (it->is_number_integer()) return std::to_string(it->get<std::int64_t>());
  throw FileError(path, where + ": '" + key + "' is not a string");
}

CameraLoadResult ParseJsonCameras(const std::string& text, const std::string& path) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    throw FileError(path, std::string("invalid JSON: ") + e.what());
  }
  if (doc.is_object() && doc.contains("cameras")) doc = doc["cameras"];
  if (!doc.is_array()) throw FileError(path, "expected a JSON list of cameras");
  if (doc.empty()) throw FileError(path, "the camera list is empty");
  CameraLoadResult res;
  for (std::size_t i = 0; i < doc.size(); ++i) {
    const json& e = doc[i];
    std::string where = "camera " + std::to_string(i);
    if (!e.is_object()) throw FileError(path, where + ": not a JSON object");
    const bool inria = e.contains("rotation") && e.contains("position");
    const bool list = e.contains("W2C");
    if (!inria && !list)
      throw FileError(path, where + ": neither an INRIA entry (rotation, position) nor a camera-list entry (W2C)");
    const std::string format = list ? "list" : "inria";
    if (i == 0) res.format = format;
    else if (format != res.format) throw FileError(path, where + ": mixes INRIA and camera-list entries");
    Camera c;
    c.name = NameOf(e, list ? "name" : "img_name", path, where);
    where += " ('" + c.name + "')";
    c.width = Size(e, "width", path, where);
    c.height = Size(e, "height", path, where);
    c.fx = Num(e, "fx", path, where);
    c.fy = Num(e, "fy", path, where);
    if (list) {
      const Eigen::MatrixXd w2c = Matrix(e, "W2C", 4, 4, path, where);
      if (!w2c.allFinite()) throw FileError(path, where + ": W2C has non-finite values");
      if ((w2c.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
        throw FileError(path, where + ": the last row of W2C must be [0, 0, 0, 1]");
      c.R = w2c.topLeftCorner<3, 3>();
      c.t = w2c.topRightCorner<3, 1>();
      c.cx = e.contains("cx") ? Num(e, "cx", path, where) : c.width / 2.0;
      c.cy = e.contains("cy") ? Num(e, "cy", path, where) : c.height / 2.0;
    } else {
      const Eigen::Matrix3d rot = Matrix(e, "rotation", 3, 3, path, where);
      const Eigen::Vector3d pos = Matrix(e, "position", 1, 3, path, where).transpose();
      if (!rot.allFinite() || !pos.allFinite()) throw FileError(path, where + ": pose has non-finite values");
      c.R = rot.transpose();  // rotation is camera-to-world
      c.t = -c.R * pos;
      c.cx = c.width / 2.0;
      c.cy = c.height / 2.0;
    }
    Validate(c, path, where);
    WarnPrincipalPoint(c, res.warnings);
    res.cameras.push_back(std::move(c));
  }
  return res;
}

// Splits a line into whitespace-separated tokens.
std::vector<std::string> Tokens(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> out;
  std::string t;
  while (s >> t) out.push_back(t);
  return out;
}

double ParseDouble(const std::string& tok, const std::string& path, std::size_t line) {
  try {
    std::size_t used = 0;
    const double v = std::stod(tok, &used);
    if (used != tok.size()) throw std::invalid_argument(tok);
    return v;
  } catch (const std::exception&) {
    throw FileError(path, "line " + std::to_string(line) + ": '" + tok + "' is not a number");
  }
}

bool IsBlank(const std::string& line) { return line.find_first_not_of(" \t\r\n\v\f") == std::string::npos; }
bool IsComment(const std::string& line) {
  const auto b = line.find_first_not_of(" \t");
  return b != std::string::npos && line[b] == '#';
}

struct Intrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

std::unordered_map<std::string, Intrinsics> ParseColmapCameras(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::unordered_map<std::string, Intrinsics> cams;
  std::string line;
  std::size_t lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (IsBlank(line) || IsComment(line)) continue;
    const auto tok = Tokens(line);
    const std::string where = "line " + std::to_string(lineno);
    if (tok.size() < 4) throw FileError(path, where + ": expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
    const std::string& model = tok[1];
    Intrinsics k;
    const double w = ParseDouble(tok[2], path, lineno), h = ParseDouble(tok[3], path, lineno);
    if (!(w >= 1 && w <= 1e6 && h >= 1 && h <= 1e6) || w != std::floor(w) || h != std::floor(h))
      throw FileError(path, where + ": width and height must be positive integers");
    k.width = static_cast<int>(w);
    k.height = static_cast<int>(h);
    std::vector<double> p;
    for (std::size_t i = 4; i < tok.size(); ++i) p.push_back(ParseDouble(tok[i], path, lineno));
    if (model == "PINHOLE") {
      if (p.size() != 4) throw FileError(path, where + ": PINHOLE needs 4 parameters (fx fy cx cy)");
      k.fx = p[0], k.fy = p[1], k.cx = p[2], k.cy = p[3];
    } else if (model == "SIMPLE_PINHOLE") {
      if (p.size() != 3) throw FileError(path, where + ": SIMPLE_PINHOLE needs 3 parameters (f cx cy)");
      k.fx = k.fy = p[0], k.cx = p[1], k.cy = p[2];
    } else {
      throw FileError(path, where + ": camera model " + model +
                                " is not supported; undistort the images first (colmap image_undistorter) to "
                                "get PINHOLE cameras");
    }
    if (!cams.emplace(tok[0], k).second) throw FileError(path, where + ": duplicate camera id " + tok[0]);
  }
  return cams;
}

CameraLoadResult ParseColmap(const std::string& cameras_text, const std::string& images_text,
                             const std::string& cameras_txt, const std::string& images_txt) {
  const auto intr = ParseColmapCameras(cameras_text, cameras_txt);
  std::istringstream in(images_text);
  CameraLoadResult res;
  res.format = "colmap";
  std::string line;
  std::size_t lineno = 0;
  bool expect_image = true;  // the line after an image line lists its 2D points (possibly empty)
  while (std::getline(in, line)) {
    ++lineno;
    if (IsComment(line)) continue;
    if (!expect_image) {
      expect_image = true;
      continue;
    }
    if (IsBlank(line)) continue;
    expect_image = false;
    const auto tok = Tokens(line);
    const std::string where = "line " + std::to_string(lineno);
    if (tok.size() < 10)
      throw FileError(images_txt, where + ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    double v[7];
    for (int i = 0; i < 7; ++i) v[i] = ParseDouble(tok[1 + i], images_txt, lineno);
    std::string name = tok[9];
    for (std::size_t i = 10; i < tok.size(); ++i) name += " " + tok[i];  // names may hold spaces
    auto it = intr.find(tok[8]);
    if (it == intr.end())
      throw FileError(images_txt, where + ": camera id " + tok[8] + " is not in " + cameras_txt);
    Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    const double norm = q.norm();
    if (!std::isfinite(norm) || norm < 1e-12) throw FileError(images_txt, where + ": invalid quaternion");
    q.coeffs() /= norm;
    Camera c;
    c.name = fs::path(name).stem().string();
    c.width = it->second.width;
    c.height = it->second.height;
    c.fx = it->second.fx;
    c.fy = it->second.fy;
    c.cx = it->second.cx;
    c.cy = it->second.cy;
    c.R = q.toRotationMatrix();
    c.t = Eigen::Vector3d(v[4], v[5], v[6]);
    Validate(c, images_txt, where + " ('" + name + "')");
    WarnPrincipalPoint(c, res.warnings);
    res.cameras.push_back(std::move(c));
  }
  if (res.cameras.empty()) throw FileError(images_txt, "no images listed");
  return res;
}

CameraLoadResult ReadColmap(const std::string& cameras_txt, const std::string& images_txt) {
  return ParseColmap(ReadText(cameras_txt), ReadText(images_txt), cameras_txt, images_txt);
}

json Rows(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (int r = 0; r < m.rows(); ++r) {
    json row = json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

CameraLoadResult ReadCameras(const std::string& path) {
  std::error_code ec;
  const fs::path p(path);
  CameraLoadResult res;
  if (fs::is_directory(p, ec)) {
    const fs::path cams = p / "cameras.txt", imgs = p / "images.txt";
    if (!fs::exists(cams, ec) || !fs::exists(imgs, ec))
      throw FileError(path, "a COLMAP folder must hold cameras.txt and images.txt (text model)");
    res = ReadColmap(cams.string(), imgs.string());
  } else if (!fs::exists(p, ec)) {
    throw FileError(path, "no such file or folder");
  } else if (p.filename() == "cameras.txt" || p.filename() == "images.txt") {
    const fs::path dir = p.parent_path();
    const fs::path cams = dir / "cameras.txt", imgs = dir / "images.txt";
    if (!fs::exists(cams, ec) || !fs::exists(imgs, ec))
      throw FileError(path, "COLMAP text model needs both cameras.txt and images.txt beside each other");
    res = ReadColmap(cams.string(), imgs.string());
  } else {
    res = ParseJsonCameras(ReadText(path), path);
  }
  for (auto& w : MakeViewNamesSafe(res.cameras)) res.warnings.push_back(std::move(w));
  return res;
}

std::string SafeFileName(std::string name) {
  for (char& ch : name)
    if (ch == '/' || ch == '\\' || ch == ':' || static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) ch = '_';
  if (name.size() > 160) name.resize(160);
  return name.empty() || name == "." || name == ".." ? "view" : name;
}

std::vector<std::string> MakeViewNamesSafe(std::vector<Camera>& cameras) {
  std::vector<std::string> warnings;
  std::set<std::string> taken;
  for (Camera& c : cameras) {
    const std::string safe = SafeFileName(c.name);
    std::string name = safe;
    for (int k = 2; taken.count(name); ++k) name = safe.substr(0, 150) + "_" + std::to_string(k);
    taken.insert(name);
    if (name == c.name) continue;
    std::string shown = c.name.substr(0, 80);
    for (char& ch : shown)
      if (static_cast<unsigned char>(ch) < 0x20) ch = '?';
    warnings.push_back("camera name '" + shown + "' " +
                       (SafeFileName(c.name) == c.name ? "occurs more than once" : "is not a safe file name") +
                       ": this view is named '" + name + "'");
    c.name = name;
  }
  return warnings;
}

CameraLoadResult ParseCamerasJson(const std::string& text, const std::string& name) {
  return ParseJsonCameras(text, name);
}

CameraLoadResult ParseColmapText(const std::string& cameras_text, const std::string& images_text,
                                 const std::string& cameras_name, const std::string& images_name) {
  return ParseColmap(cameras_text, images_text, cameras_name, images_name);
}

void WriteCameraList(const std::string& path, const std::vector<Camera>& cameras) {
  json doc = json::array();
  for (const Camera& c : cameras) {
    Eigen::Matrix4d w2c = Eigen::Matrix4d::Identity();
    w2c.topLeftCorner<3, 3>() = c.R;
    w2c.topRightCorner<3, 1>() = c.t;
    doc.push_back({{"name", c.name}, {"W2C", Rows(w2c)}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx},
                   {"cy", c.cy}, {"width", c.width}, {"height", c.height}});
  }
  WriteFileAtomically(path, doc.dump(1) + "\n");
}

void WriteInriaCameras(const std::string& path, const std::vector<Camera>& cameras) {
  json doc = json::array();
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    const Eigen::Vector3d centre = c.Centre();
    json pos = {centre.x(), centre.y(), centre.z()};
    doc.push_back({{"id", i}, {"img_name", c.name}, {"width", c.width}, {"height", c.height},
                   {"position", pos}, {"rotation", Rows(c.R.transpose())}, {"fy", c.fy}, {"fx", c.fx}});
  }
  WriteFileAtomically(path, doc.dump(1) + "\n");
}

std::vector<Camera> SelectViews(const std::vector<Camera>& cameras, const std::string& views) {
  auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return std::string();
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
  };
  if (trim(views) == "all" || trim(views).empty()) return cameras;
  std::vector<Camera> out;
  std::set<std::string> taken;
  std::stringstream ss(views);
  std::string name;
  while (std::getline(ss, name, ',')) {
    name = trim(name);
    if (name.empty() || taken.count(name)) continue;
    bool found = false;
    for (const Camera& c : cameras)
      if (c.name == name) {
        out.push_back(c);
        found = true;
        break;
      }
    if (!found) {
      std::string known;
      for (std::size_t i = 0; i < cameras.size() && i < 5; ++i) known += (i ? ", " : "") + cameras[i].name;
      if (cameras.size() > 5) known += ", ... (" + std::to_string(cameras.size()) + " cameras)";
      throw Error("--views: unknown view '" + name + "' (known: " + known + ")");
    }
    taken.insert(name);
  }
  return out;
}

}  // namespace al
