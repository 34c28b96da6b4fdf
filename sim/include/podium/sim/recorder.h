#pragma once
/// Recording: one frame per call (time, q, q̇, link poses, COM, contacts), written as a
/// compact trajectory file for the dashboard's browser replay (format in sim/README.md; it
/// carries the props and terrain) or as BVH for animation tools.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "podium/sim/world.h"

namespace podium::sim {

struct Frame {
  double time_s = 0.0;
  Eigen::VectorXd q;                               // nq
  Eigen::VectorXd qd;                              // nv (joint velocities; sim/README.md glossary)
  std::vector<Eigen::Matrix<double, 7, 1>> links;  // per link: position (3), quaternion wxyz (4), world
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  std::vector<char> body_contacts;  // per body
};

class Recorder {
 public:
  explicit Recorder(ModelPtr model) : model_(std::move(model)) {}
  /// Appends the world's current state as a frame (call once per control step, or per recorded
  /// simulation step: World::set_substep_observer); keeps the world's terrain and props for the
  /// file (the latest recorded).
  void record(World& world);
  const std::vector<Frame>& frames() const { return frames_; }
  const CharacterModel& model() const { return *model_; }
  const TerrainConfig& terrain() const { return terrain_; }
  void clear() { frames_.clear(); }

 private:
  ModelPtr model_;
  std::vector<Frame> frames_;
  TerrainConfig terrain_;
};

/// Writes the JSON-lines trajectory file: a header line (model, links with their shapes, joint
/// names), then one line per frame. Throws base::RuntimeError if the file cannot be written.
void write_trajectory(const Recorder& recorder, const std::filesystem::path& path);
/// Writes a BVH file (one BVH joint per link, ZXY Euler angles in degrees, positions in metres).
void write_bvh(const Recorder& recorder, const std::filesystem::path& path, double frame_time_s);

}  // namespace podium::sim
