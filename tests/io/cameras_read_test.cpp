// Camera files: real INRIA cameras.json files, COLMAP text generated from them (same W2C),
// the plain JSON list, round trips, validation errors and view selection.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <iomanip>

#include <nlohmann/json.hpp>

#include "al/core/error.hpp"
#include "al/io/cameras.hpp"
#include "test_data.hpp"

namespace {

double OrthoError(const Eigen::Matrix3d& r) {
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

void WriteText(const std::filesystem::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

template <typename F>
void ExpectError(F f, const std::string& needle) {
  try {
    f();
    FAIL() << "no error (" << needle << ")";
  } catch (const al::Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// COLMAP text model of the given cameras (PINHOLE and SIMPLE_PINHOLE alternating).
void WriteColmap(const std::filesystem::path& dir, const std::vector<al::Camera>& cams) {
  std::ofstream c(dir / "cameras.txt"), im(dir / "images.txt");
  c << std::setprecision(17) << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  im << std::setprecision(17) << "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const auto& k = cams[i];
    if (i % 2 == 0)
      c << i + 1 << " PINHOLE " << k.width << " " << k.height << " " << k.fx << " " << k.fy << " " << k.cx << " " << k.cy << "\n";
    else
      c << i + 1 << " SIMPLE_PINHOLE " << k.width << " " << k.height << " " << k.fx << " " << k.cx << " " << k.cy << "\n";
    Eigen::Quaterniond q(k.R);
    if (i % 3 == 0) q.coeffs() = -q.coeffs();  // q and -q are the same rotation
    im << i + 1 << " " << q.w() << " " << q.x() << " " << q.y() << " " << q.z() << " " << k.t.x() << " " << k.t.y()
       << " " << k.t.z() << " " << i + 1 << " images/" << k.name << ".JPG\n";
    if (i % 2 == 0) im << "\n";  // empty 2D points line
    else im << "1.5 2.5 -1 10.25 20.75 42\n";
  }
}

void ExpectSamePose(const al::Camera& a, const al::Camera& b, double tol) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_NEAR(a.fx, b.fx, 1e-9 * a.fx);
  EXPECT_NEAR(a.fy, b.fy, 1e-9 * a.fy);
  EXPECT_LT((a.R - b.R).cwiseAbs().maxCoeff(), tol) << a.name;
  EXPECT_LT((a.t - b.t).cwiseAbs().maxCoeff(), tol * (1 + a.t.norm())) << a.name;
}

TEST(CamerasRead, RealInriaExample) {
  AL_REQUIRE_SHARED_DATA(data);
  const std::string path = (data / "parsers" / "cameras_example.json").string();
  const auto res = al::ReadCameras(path);
  EXPECT_EQ(res.format, "inria");
  ASSERT_EQ(res.cameras.size(), 97u);
  EXPECT_TRUE(res.warnings.empty());
  std::ifstream in(path);
  const auto doc = nlohmann::json::parse(in);
  for (std::size_t i = 0; i < res.cameras.size(); ++i) {
    const al::Camera& c = res.cameras[i];
    EXPECT_EQ(c.name, doc[i]["img_name"].get<std::string>());
    EXPECT_EQ(c.width, 3958);
    EXPECT_EQ(c.height, 2968);
    EXPECT_DOUBLE_EQ(c.cx, 1979.0);
    EXPECT_DOUBLE_EQ(c.cy, 1484.0);
    const Eigen::Vector3d pos(doc[i]["position"][0].get<double>(), doc[i]["position"][1].get<double>(),
                              doc[i]["position"][2].get<double>());
    EXPECT_LT((c.Centre() - pos).norm(), 1e-9 * (1 + pos.norm())) << i;
    EXPECT_LT(OrthoError(c.R), 1e-6) << i;
    EXPECT_GT(c.R.determinant(), 0.0);
    // Camera-to-world columns are the camera axes: R's rows.
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(c.R(r, k), doc[i]["rotation"][k][r].get<double>());
  }
}

TEST(CamerasRead, RealRefs9kCameras) {
  AL_REQUIRE_SHARED_DATA(data);
  const auto res = al::ReadCameras((data / "refs_9k" / "cameras.json").string());
  ASSERT_EQ(res.cameras.size(), 2u);
  EXPECT_EQ(res.cameras[0].name, "cam0");
  EXPECT_EQ(res.cameras[1].name, "cam1");
  EXPECT_EQ(res.cameras[0].width, 320);
  EXPECT_EQ(res.cameras[0].height, 240);
  EXPECT_EQ(res.cameras[0].fx, 384.0);
  EXPECT_TRUE(res.cameras[0].R.isIdentity(0));
  EXPECT_TRUE(res.cameras[0].t.isZero(0));
  // cam1 sits at its position and looks along the third row of R.
  const al::Camera& c1 = res.cameras[1];
  EXPECT_LT((c1.Centre() - Eigen::Vector3d(-4.74104503201599, 5.0, -21.852288026758124)).norm(), 1e-12);
  EXPECT_LT(OrthoError(c1.R), 1e-12);
}

TEST(CamerasRead, ColmapTextMatchesInria) {
  AL_REQUIRE_SHARED_DATA(data);
  const auto inria = al::ReadCameras((data / "parsers" / "cameras_example.json").string());
  const auto dir = al::test::TempDir();
  WriteColmap(dir, inria.cameras);
  for (const auto& p : {dir, dir / "cameras.txt", dir / "images.txt"}) {
    const auto col = al::ReadCameras(p.string());
    EXPECT_EQ(col.format, "colmap");
    ASSERT_EQ(col.cameras.size(), inria.cameras.size());
    EXPECT_TRUE(col.warnings.empty());
    for (std::size_t i = 0; i < col.cameras.size(); ++i) {
      ExpectSamePose(inria.cameras[i], col.cameras[i], 1e-9);
      EXPECT_DOUBLE_EQ(col.cameras[i].cx, inria.cameras[i].cx);
    }
  }
}

TEST(CamerasRead, ColmapErrorsAndPrincipalPointWarning) {
  const auto dir = al::test::TempDir();
  WriteText(dir / "cameras.txt", "1 OPENCV 640 480 500 500 320 240 0.1 0.01 0 0\n");
  WriteText(dir / "images.txt", "1 1 0 0 0 0 0 0 1 a.png\n\n");
  ExpectError([&] { al::ReadCameras(dir.string()); }, "undistort");
  WriteText(dir / "cameras.txt", "# c\n1 PINHOLE 640 480 500 510 300 240\n");
  WriteText(dir / "images.txt", "1 1 0 0 0 0 0 0 2 a.png\n\n");
  ExpectError([&] { al::ReadCameras(dir.string()); }, "camera id 2");
  WriteText(dir / "images.txt", "1 1 0 0 zero 0 0 0 1 a.png\n\n");
  ExpectError([&] { al::ReadCameras(dir.string()); }, "'zero' is not a number");
  WriteText(dir / "images.txt", "1 0 0 0 0 0 0 0 1 a.png\n\n");
  ExpectError([&] { al::ReadCameras(dir.string()); }, "quaternion");
  // Off-centre principal point: loaded, with a warning; unnormalised quaternion is normalised.
  WriteText(dir / "images.txt", "1 2 0 0 0 1 2 3 1 sub dir/my img.png\n\n2 0.7071067811865476 0 0.7071067811865476 0 0 0 0 1 b.jpg\n1 2 3\n");
  const auto res = al::ReadCameras((dir / "images.txt").string());
  ASSERT_EQ(res.cameras.size(), 2u);
  EXPECT_EQ(res.cameras[0].name, "my img");
  EXPECT_EQ(res.cameras[1].name, "b");
  EXPECT_TRUE(res.cameras[0].R.isIdentity(1e-15));
  EXPECT_EQ(res.cameras[0].t, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(res.cameras[0].fy, 510.0);
  EXPECT_EQ(res.warnings.size(), 2u);  // one per camera: cx = 300 vs 320
  // Rotation about y by 90 degrees: camera z axis (third row) = world -x.
  EXPECT_LT((res.cameras[1].R.row(2).transpose() - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
  std::filesystem::remove(dir / "cameras.txt");
  ExpectError([&] { al::ReadCameras(dir.string()); }, "cameras.txt");
}

al::Camera MakeCamera(const std::string& name, double angle) {
  al::Camera c;
  c.name = name;
  c.width = 640;
  c.height = 480;
  c.fx = 500.5;
  c.fy = 501.25;
  c.cx = 320;
  c.cy = 240;
  c.R = Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  c.t = Eigen::Vector3d(0.1, -2.0, angle);
  return c;
}

TEST(CamerasRead, ListAndInriaWritersRoundTrip) {
  const auto dir = al::test::TempDir();
  std::vector<al::Camera> cams = {MakeCamera("a", 0.3), MakeCamera("b", 2.0), MakeCamera("c", -1.0)};
  cams[2].cx = 330.0;  // off-centre: kept in the list format, warned about
  al::WriteCameraList((dir / "list.json").string(), cams);
  const auto list = al::ReadCameras((dir / "list.json").string());
  EXPECT_EQ(list.format, "list");
  ASSERT_EQ(list.cameras.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(list.cameras[i].R, cams[i].R);  // doubles round-trip exactly through JSON
    EXPECT_EQ(list.cameras[i].t, cams[i].t);
    EXPECT_EQ(list.cameras[i].cx, cams[i].cx);
    EXPECT_EQ(list.cameras[i].fy, cams[i].fy);
  }
  ASSERT_EQ(list.warnings.size(), 1u);
  EXPECT_NE(list.warnings[0].find("'c'"), std::string::npos);

  al::WriteInriaCameras((dir / "cameras.json").string(), cams);
  const auto inria = al::ReadCameras((dir / "cameras.json").string());
  EXPECT_EQ(inria.format, "inria");
  for (std::size_t i = 0; i < 3; ++i) ExpectSamePose(cams[i], inria.cameras[i], 1e-14);
  EXPECT_EQ(inria.cameras[2].cx, 320.0);  // INRIA has no principal point
}

TEST(CamerasRead, ValidationErrorsNameTheEntry) {
  const auto dir = al::test::TempDir();
  const std::string p = (dir / "c.json").string();
  auto write_list = [&](const std::vector<al::Camera>& cams) { al::WriteCameraList(p, cams); };
  al::Camera bad = MakeCamera("skewed", 0.5);
  bad.R *= 1.01;
  write_list({MakeCamera("ok", 0.1), bad});
  ExpectError([&] { al::ReadCameras(p); }, "camera 1 ('skewed'): rotation is not orthonormal");
  bad = MakeCamera("mirror", 0.5);
  bad.R.row(0) *= -1;
  write_list({bad});
  ExpectError([&] { al::ReadCameras(p); }, "reflection");
  bad = MakeCamera("neg", 0.5);
  bad.fx = -1;
  write_list({bad});
  ExpectError([&] { al::ReadCameras(p); }, "focal");
  bad = MakeCamera("zero", 0.5);
  bad.width = 0;
  write_list({bad});
  ExpectError([&] { al::ReadCameras(p); }, "'width' must be a positive integer");

  WriteText(p, "[{\"img_name\": \"x\", \"width\": 10, \"height\": 10, \"fx\": 5, \"fy\": 5, \"position\": [0, 0], "
               "\"rotation\": [[1,0,0],[0,1,0],[0,0,1]]}]");
  ExpectError([&] { al::ReadCameras(p); }, "'position' must be");
  WriteText(p, "[{\"img_name\": \"x\", \"width\": 10, \"height\": 10, \"fy\": 5, \"position\": [0, 0, 0], "
               "\"rotation\": [[1,0,0],[0,1,0],[0,0,1]]}]");
  ExpectError([&] { al::ReadCameras(p); }, "missing 'fx'");
  WriteText(p, "[{\"name\": \"x\"}]");
  ExpectError([&] { al::ReadCameras(p); }, "neither");
  WriteText(p, "[{\"name\": \"x\", \"W2C\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], \"fx\": 1e999, \"fy\": 5, "
               "\"width\": 4, \"height\": 4}]");
  ExpectError([&] { al::ReadCameras(p); }, p + ": ");
  WriteText(p, "[{\"name\": \"x\", \"W2C\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]], \"fx\": 5, \"fy\": 5, "
               "\"width\": 4, \"height\": 4}]");
  ExpectError([&] { al::ReadCameras(p); }, "last row");
  WriteText(p, "[{\"name\": ");
  ExpectError([&] { al::ReadCameras(p); }, "invalid JSON");
  WriteText(p, "[]");
  ExpectError([&] { al::ReadCameras(p); }, "empty");
  ExpectError([&] { al::ReadCameras((dir / "absent.json").string()); }, "absent.json");
}

TEST(CamerasRead, SelectViews) {
  std::vector<al::Camera> cams;
  for (int i = 0; i < 8; ++i) cams.push_back(MakeCamera(std::string(1, 'v').append(std::to_string(i)), 0.1 * i));
  EXPECT_EQ(al::SelectViews(cams, "all").size(), 8u);
  const auto two = al::SelectViews(cams, "v5, v2,v5");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].name, "v5");
  EXPECT_EQ(two[1].name, "v2");
  EXPECT_EQ(two[0].R, cams[5].R);
  ExpectError([&] { al::SelectViews(cams, "v1,nope"); }, "unknown view 'nope' (known: v0, v1, v2, v3, v4, ... (8 cameras))");
}

}  // namespace
