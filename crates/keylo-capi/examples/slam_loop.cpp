// keylo as the LiDAR front end of a minimal C++ SLAM loop.
//
// Reads a KITTI-style folder of scans (`*.bin`: float32 x, y, z, intensity per point, sorted
// by name), registers each with keylo, feeds a motion prior when one is given (a KITTI pose
// file standing in for an IMU or wheel odometry: the prior of frame k is P[k-1]^-1 * P[k]),
// keeps a keyframe every `KEYFRAME_M` metres, and prints every pose as a KITTI line.
//
//   slam_loop CONFIG.toml SCANS_DIR [PRIOR_POSES.txt]
//
// Output: `pose K r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz`, `stats K points map_points
// iterations register_ms`, `keyframe K x y z`, and `map N` (local-map points at the end).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "keylo.h"

namespace {

using Matrix = std::array<double, 16>;  // row-major 4x4

// A keylo pipeline owned by a C++ object: freed once, errors thrown with keylo's message.
class Odometry {
 public:
  Odometry(const std::string &toml, const std::string &base_dir) {
    char error[1024] = {0};
    handle_.reset(keylo_pipeline_new(toml.c_str(), base_dir.c_str(), error, sizeof error));
    if (!handle_) throw std::runtime_error(std::string("keylo_pipeline_new: ") + error);
  }

  void set_motion_prior(const Matrix &delta) { check(keylo_pipeline_set_motion_prior(get(), delta.data())); }

  void push(double stamp, const std::vector<float> &xyz, const std::vector<float> &intensity) {
    check(keylo_pipeline_push_points(get(), stamp, xyz.data(), nullptr, intensity.data(), xyz.size() / 3));
  }

  KeyloPose pose() {
    KeyloPose pose{};
    pose.size = sizeof pose;
    check(keylo_pipeline_pose(get(), &pose));
    return pose;
  }

  KeyloFrameStats stats() {
    KeyloFrameStats stats{};
    stats.size = sizeof stats;
    check(keylo_pipeline_stats(get(), &stats));
    return stats;
  }

  size_t local_map_points() {
    const double *xyz = nullptr;
    size_t n = 0;
    check(keylo_pipeline_local_map(get(), &xyz, &n));
    return n;
  }

 private:
  struct Free {
    void operator()(KeyloPipeline *p) const { keylo_pipeline_free(p); }
  };
  std::unique_ptr<KeyloPipeline, Free> handle_;

  KeyloPipeline *get() const { return handle_.get(); }
  void check(int rc) const {
    if (rc != KEYLO_CAPI_OK) throw std::runtime_error(keylo_pipeline_error(get()));
  }
};

std::string read_text(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One KITTI scan: xyz and intensity.
void read_scan(const std::filesystem::path &path, std::vector<float> &xyz, std::vector<float> &intensity) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  const auto bytes = static_cast<size_t>(in.tellg());
  if (bytes % 16 != 0) throw std::runtime_error(path.string() + ": size is not a multiple of 16 bytes");
  std::vector<float> raw(bytes / 4);
  in.seekg(0);
  in.read(reinterpret_cast<char *>(raw.data()), static_cast<std::streamsize>(bytes));
  xyz.clear();
  intensity.clear();
  for (size_t i = 0; i + 3 < raw.size(); i += 4) {
    xyz.insert(xyz.end(), {raw[i], raw[i + 1], raw[i + 2]});
    intensity.push_back(raw[i + 3]);
  }
}

// KITTI poses: 12 numbers per line (a row-major 3x4), as 4x4 matrices.
std::vector<Matrix> read_poses(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<Matrix> poses;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    Matrix m{};
    for (int i = 0; i < 12; i++)
      if (!(s >> m[i])) throw std::runtime_error(path + ": a line without 12 numbers");
    m[15] = 1.0;
    poses.push_back(m);
  }
  return poses;
}

Matrix multiply(const Matrix &a, const Matrix &b) {
  Matrix c{};
  for (int r = 0; r < 4; r++)
    for (int k = 0; k < 4; k++)
      for (int j = 0; j < 4; j++) c[4 * r + j] += a[4 * r + k] * b[4 * k + j];
  return c;
}

// Inverse of a rigid transform: [R^T, -R^T t].
Matrix rigid_inverse(const Matrix &m) {
  Matrix inv{};
  for (int r = 0; r < 3; r++) {
    for (int c = 0; c < 3; c++) inv[4 * r + c] = m[4 * c + r];
    inv[4 * r + 3] = -(m[r] * m[3] + m[4 + r] * m[7] + m[8 + r] * m[11]);
  }
  inv[15] = 1.0;
  return inv;
}

constexpr double KEYFRAME_M = 0.5;

}  // namespace

int main(int argc, char **argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: slam_loop CONFIG.toml SCANS_DIR [PRIOR_POSES.txt]\n");
    return 2;
  }
  try {
    const std::filesystem::path config(argv[1]);
    Odometry odometry(read_text(config.string()), config.parent_path().string());
    std::vector<std::filesystem::path> scans;
    for (const auto &entry : std::filesystem::directory_iterator(argv[2]))
      if (entry.path().extension() == ".bin") scans.push_back(entry.path());
    std::sort(scans.begin(), scans.end());
    if (scans.empty()) throw std::runtime_error(std::string(argv[2]) + ": no .bin scans");
    const std::vector<Matrix> prior = argc == 4 ? read_poses(argv[3]) : std::vector<Matrix>{};
    std::vector<float> xyz, intensity;
    std::array<double, 3> last_keyframe{};
    bool any_keyframe = false;
    for (size_t k = 0; k < scans.size(); k++) {
      if (k > 0 && k < prior.size()) odometry.set_motion_prior(multiply(rigid_inverse(prior[k - 1]), prior[k]));
      read_scan(scans[k], xyz, intensity);
      odometry.push(0.1 * static_cast<double>(k), xyz, intensity);
      const KeyloPose pose = odometry.pose();
      const KeyloFrameStats stats = odometry.stats();
      std::printf("pose %zu", k);
      for (int i = 0; i < 12; i++) std::printf(" %.9f", pose.matrix[i]);
      std::printf("\nstats %zu %llu %llu %llu %.3f\n", k, static_cast<unsigned long long>(stats.cloud_points),
                  static_cast<unsigned long long>(stats.map_points),
                  static_cast<unsigned long long>(stats.iterations), stats.register_ms);
      const std::array<double, 3> t = {pose.translation[0], pose.translation[1], pose.translation[2]};
      const double moved = std::hypot(t[0] - last_keyframe[0], t[1] - last_keyframe[1], t[2] - last_keyframe[2]);
      if (!any_keyframe || moved >= KEYFRAME_M) {
        std::printf("keyframe %zu %.6f %.6f %.6f\n", k, t[0], t[1], t[2]);
        last_keyframe = t;
        any_keyframe = true;
      }
    }
    std::printf("map %zu\n", odometry.local_map_points());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "slam_loop: %s\n", e.what());
    return 1;
  }
  return 0;
}
