#include "podium/character/observations.h"

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/sim/dynamics.h"

namespace podium::character {

namespace {

Eigen::Matrix3d heading_of(const sim::CharacterData& d) { return heading_rotation(heading_yaw(d.links[0].R)); }

void put(std::span<double> out, std::size_t& at, const Eigen::Vector3d& v) {
  out[at++] = v.x(), out[at++] = v.y(), out[at++] = v.z();
}

}  // namespace

void link_velocities(const sim::CharacterModel& model, const sim::CharacterData& d, std::vector<Eigen::Vector3d>& omega,
                     std::vector<Eigen::Vector3d>& velocity) {
  const auto& links = model.links();
  omega.resize(links.size());
  velocity.resize(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    const sim::Link& l = links[i];
    const Eigen::Matrix3d& R = d.links[i].R;
    if (l.parent < 0) {  // root: ω and v of its origin in its own frame
      omega[i] = R * d.qd.segment<3>(l.v_index);
      velocity[i] = R * d.qd.segment<3>(l.v_index + 3);
      continue;
    }
    const Eigen::Vector3d rel = l.joint == sim::JointType::revolute ? Eigen::Vector3d(l.axis * d.qd(l.v_index))
                                                                    : Eigen::Vector3d(d.qd.segment<3>(l.v_index));
    omega[i] = omega[l.parent] + R * rel;  // joint rates are in the child frame
    velocity[i] = velocity[l.parent] + omega[l.parent].cross(d.links[i].p - d.links[l.parent].p);
  }
}

void JointAngles::write(const CharacterEnv& env, std::span<double> out) const {
  const std::vector<double> pose = bridge_.pose(env.world().data().q);
  std::copy(pose.begin(), pose.end(), out.begin());
}

void JointVelocities::write(const CharacterEnv& env, std::span<double> out) const {
  const Eigen::VectorXd& qd = env.world().data().qd;
  for (int i = 6; i < qd.size(); ++i) out[i - 6] = qd(i);
}

void RootVelocity::write(const CharacterEnv& env, std::span<double> out) const {
  const Eigen::VectorXd& qd = env.world().data().qd;
  for (int i = 0; i < 6; ++i) out[i] = qd(i);
}

void HeadHeight::write(const CharacterEnv& env, std::span<double> out) const { out[0] = env.features().head_height_m; }

std::size_t LinkStates::size(const sim::CharacterModel& model) const {
  return model.bodies().size() * ((blocks_.positions ? 3 : 0) + (blocks_.rotations ? 6 : 0) + (blocks_.velocities ? 6 : 0));
}

void LinkStates::write(const CharacterEnv& env, std::span<double> out) const {
  const auto& model = env.model();
  const auto& d = env.world().data();
  const Eigen::Matrix3d Ht = frame_ == Frame::world ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(heading_of(d).transpose());
  std::vector<Eigen::Vector3d> omega, velocity;
  if (blocks_.velocities) link_velocities(model, d, omega, velocity);
  std::size_t at = 0;
  for (std::size_t b = 0; b < model.bodies().size(); ++b) {
    const sim::Body& body = model.bodies()[b];
    const auto& link = d.links[body.link];
    const Eigen::Vector3d p = sim::body_point(model, d, static_cast<int>(b), Eigen::Vector3d::Zero());
    if (blocks_.positions) put(out, at, Ht * (p - d.links[0].p));
    if (blocks_.rotations) {
      const Eigen::Matrix3d R = Ht * link.R;
      put(out, at, R.col(0));
      put(out, at, R.col(1));
    }
    if (blocks_.velocities) {
      put(out, at, Ht * (velocity[body.link] + omega[body.link].cross(p - link.p)));
      put(out, at, Ht * omega[body.link]);
    }
  }
}

void EndEffectors::write(const CharacterEnv& env, std::span<double> out) const {
  std::size_t at = 0;
  for (const Eigen::Vector3d& e : env.features().end_effectors) put(out, at, e);
}

void CenterOfMass::write(const CharacterEnv& env, std::span<double> out) const {
  const sim::Observation& f = env.features();
  const Eigen::Matrix3d Ht = heading_of(env.world().data()).transpose();
  out[0] = f.com.z() - env.world().terrain().height(f.com.x(), f.com.y());
  std::size_t at = 1;
  put(out, at, Ht * f.com_vel);
}

void TorsoAxes::write(const CharacterEnv& env, std::span<double> out) const {
  const auto& model = env.model();
  const auto& d = env.world().data();
  const Eigen::Matrix3d& R = d.links[model.bodies()[model.torso_body()].link].R;
  std::size_t at = 0;
  if (vertical_only_) {
    put(out, at, R.row(2).transpose());
    return;
  }
  const Eigen::Matrix3d local = heading_of(d).transpose() * R;
  for (int c = 0; c < 3; ++c) put(out, at, local.col(c));
}

void HeightMap::write(const CharacterEnv& env, std::span<double> out) const {
  const auto& root = env.world().data().links[0];
  // Terrain::height_map gives terrain − reference; the seed's map is the root's height above it.
  const auto map = env.world().terrain().height_map(root.p.x(), root.p.y(), heading_yaw(root.R), spacing_m_, root.p.z());
  for (std::size_t k = 0; k < map.size(); ++k) out[k] = -map[k];
}

void ReferenceFrames::write(const CharacterEnv& env, std::span<double> out) const {
  if (!env.reference()) throw base::UserError("character observations: reference frames need a reference clip");
  const auto& d = env.world().data();
  const Eigen::Matrix3d Ht = heading_of(d).transpose();
  std::size_t at = 0;
  for (int k : steps_) {
    const Eigen::VectorXd q = env.reference()->sample(env.reference_time_s() + k * env.control_dt_s());
    const std::vector<double> pose = bridge_.pose(q);
    for (double v : pose) out[at++] = v;
    put(out, at, Ht * (q.head<3>() - d.links[0].p));
    const Eigen::Matrix3d R = Ht * quat_at(q, 3).normalized().toRotationMatrix();
    put(out, at, R.col(0));
    put(out, at, R.col(1));
  }
}

}  // namespace podium::character
