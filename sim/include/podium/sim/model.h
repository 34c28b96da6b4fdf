#pragma once
/// CharacterModel: the immutable description of an articulated character (docs/style.md "sim/":
/// constant model + mutable data). Built once from a model file and shared, read-only, by every
/// rollout thread (hold it as ModelPtr). Frames: z up, metres, kilograms, radians.
///
/// A model is a tree of *links*, each moved by one joint: the root link by a free joint, others
/// by a revolute (1 DoF), spherical (3 DoF) joint. A body with k hinges in the model file becomes
/// k links (the first k-1 massless); a body without joints is welded into its parent link.
/// Every link frame sits at its joint anchor and is parallel to its parent's frame at q = 0.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::sim {

enum class JointType { free, revolute, spherical };
enum class ShapeType { capsule, box, sphere };

/// A collision/visual shape, placed in its link's frame. Capsules run along the local z axis.
struct Geom {
  ShapeType type = ShapeType::sphere;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();            // centre in link frame, m
  Eigen::Quaterniond rot = Eigen::Quaterniond::Identity();  // local frame in link frame
  double radius = 0.0;                                      // capsule/sphere radius, m
  double half_length = 0.0;                                 // capsule half length (cylinder part), m
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();   // box half sizes, m
  int body = -1;                                            // owning body index
};

struct Link {
  std::string name;  // joint name (root: the root body's name)
  int parent = -1;   // parent link index, < own index; -1 for the root
  int body = -1;     // index of the body this link moves
  JointType joint = JointType::free;
  Eigen::Vector3d joint_pos = Eigen::Vector3d::Zero();  // anchor in parent link frame, m
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();      // revolute axis; spherical: twist axis (unit), link frame
  double mass = 0.0;                                    // kg (0 for a massless hinge link)
  Eigen::Vector3d com = Eigen::Vector3d::Zero();        // centre of mass, link frame, m
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();    // about the COM, link frame, kg·m²
  std::vector<Geom> geoms;                              // shapes carried by this link
  int q_index = 0, v_index = 0;                         // first entries in q (nq) and qd (nv)
  int nq = 0, nv = 0;                                   // free 7/6, revolute 1/1, spherical 4/3
  double lower = 0.0, upper = 0.0;                      // revolute angle limits, rad (lower > upper: unlimited)
  // Spherical limits: swing = the angle between `axis` and its image (a cone), twist = the angle
  // of the twist about `axis` in the swing–twist split q = q_swing q_twist.
  double swing_limit = -1.0;                     // rad (< 0: none)
  double twist_lower = 1.0, twist_upper = -1.0;  // rad (lower > upper: none)
  bool locked = false;                           // held at `lock` (a cast): revolute angle in lock(0), spherical quaternion wxyz
  Eigen::Vector4d lock = Eigen::Vector4d(1, 0, 0, 0);
  // Per-DoF torque bounds before the strength multiplier, N·m: the first nv entries (revolute:
  // (0); spherical: about the link's x, y, z axes, which may differ, as the thesis's jumper's do).
  Eigen::Vector3d torque_limit_nm = Eigen::Vector3d::Zero();
  double kp = 0.0, kd = 0.0;  // PD gains, N·m/rad and N·m·s/rad
  // Passive joint torque −damping·q̇ − stiffness·q (MuJoCo's joint damping and stiffness, spring
  // at q = 0), N·m·s/rad and N·m/rad; revolute joints only; a World applies it when
  // WorldConfig::passive_joints is set.
  double damping = 0.0, stiffness = 0.0;
  // Rotor inertia added to the joint-space inertia's diagonal at each of the joint's DoFs
  // (MuJoCo's joint armature), kg·m²; 0: none.
  double armature = 0.0;
};

/// A named rigid body (what observations, recording and contacts talk about).
struct Body {
  std::string name;
  int link = 0;                                      // link that carries it
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // body origin in that link's frame, m
};

class CharacterModel {
 public:
  /// Builds and validates a model from its JSON description (format in sim/README.md);
  /// `where` names the source in error messages. Throws base::UserError on bad input.
  static std::shared_ptr<const CharacterModel> from_json(const base::Json& json, const std::string& where);

  const std::string& name() const { return name_; }
  int nq() const { return nq_; }  // position coordinates: root 7 (pos, quat wxyz) + joints
  int nv() const { return nv_; }  // velocity DoFs: root 6 (ω, v in root frame) + joints
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Body>& bodies() const { return bodies_; }
  double total_mass() const { return total_mass_; }
  /// Body index by name, or -1.
  int find_body(const std::string& name) const;
  /// Link index by joint name, or -1.
  int find_link(const std::string& name) const;
  /// The link of joint `name`; throws base::UserError naming the model if it has no such joint.
  const Link& link(const std::string& name) const;
  /// Whether links a and b may collide with each other (self-collision filter).
  bool links_collide(int a, int b) const { return collide_[a * links_.size() + b] != 0; }
  int head_body() const { return head_; }
  int torso_body() const { return torso_; }
  const std::vector<int>& end_effector_bodies() const { return end_effectors_; }
  /// Joint configuration of the standing pose (nq; root at its standing height).
  const Eigen::VectorXd& standing_pose() const { return standing_; }
  /// Per-DoF torque limits (nv, 0 on the root), N·m.
  const Eigen::VectorXd& torque_limits() const { return torque_limits_; }
  /// Per-DoF gains (nv, 0 on the root).
  const Eigen::VectorXd& kp() const { return kp_; }
  const Eigen::VectorXd& kd() const { return kd_; }
  /// Per-DoF passive damping and stiffness (nv, 0 on the root and spherical joints).
  const Eigen::VectorXd& damping() const { return damping_; }
  const Eigen::VectorXd& stiffness() const { return stiffness_; }
  /// Per-DoF armature (nv, 0 on the root), added to the mass matrix's diagonal by CRBA and MABA.
  const Eigen::VectorXd& armature() const { return armature_; }
  bool has_armature() const { return has_armature_; }
  /// Coulomb μ of contacts between two of the character's own bodies (the file's
  /// "self_contact_friction"; MuJoCo's condim 1 is 0); nullopt: the bodies' combined μ, as any contact.
  std::optional<double> self_contact_friction() const { return self_contact_friction_; }
  /// Neutral configuration: root at the origin, identity rotations, zero angles.
  Eigen::VectorXd neutral() const;
  /// The model-file JSON this model was built from.
  const base::Json& source() const { return source_; }

 private:
  friend class ModelBuilder;
  std::string name_;
  int nq_ = 0, nv_ = 0;
  std::vector<Link> links_;
  std::vector<Body> bodies_;
  std::vector<char> collide_;
  int head_ = 0, torso_ = 0;
  std::vector<int> end_effectors_;
  double total_mass_ = 0.0;
  Eigen::VectorXd standing_, torque_limits_, kp_, kd_, damping_, stiffness_, armature_;
  bool has_armature_ = false;
  std::optional<double> self_contact_friction_;
  base::Json source_;
};

using ModelPtr = std::shared_ptr<const CharacterModel>;

/// Changes to a model made when a World is built (WorldConfig::edits), in model-file terms:
/// `remove` bodies with their subtrees (the file's top-level "remove"), and per joint name the
/// keys merged into its joint entry ("lock", "swing", "twist", "axis", "range"; sim/README.md),
/// and `mass_scale`, which multiplies every body's mass (a body's "mass", else its "density", and
/// the hinge links'), so each inertia scales with it (the geometry is unchanged).
struct ModelEdits {
  std::vector<std::string> remove;
  std::vector<std::pair<std::string, base::Json>> joints;
  double mass_scale = 1.0;
  bool empty() const { return remove.empty() && joints.empty() && mass_scale == 1.0; }
};

/// The model with `edits` applied (the model itself when there are none). Throws
/// base::UserError naming an unknown body or joint, or a bad value.
ModelPtr edit_model(const ModelPtr& model, const ModelEdits& edits);

/// Loads a model file of the project's own JSON format.
ModelPtr load_model(const std::filesystem::path& path);
/// Loads a model shipped in sim/models/ by name ("humanoid21", "humanoid34", "athlete").
ModelPtr load_shipped_model(const std::string& name);
/// The folder of shipped models (compiled in; overridable with PODIUM_SIM_MODELS).
std::filesystem::path shipped_models_dir();

/// Chain ("snake") of n capsule links joined by spherical (3 DoF) or revolute joints with
/// alternating axes; floating root. nv = 6 + 3(n−1) for spherical joints (thesis Table 2.1).
ModelPtr make_chain(int n_links, JointType joint = JointType::spherical);

/// Loads a DeepMimic character (`Skeleton.Joints`, `BodyDefs`) and optional PD controller file
/// (`PDControllers[]` with `Kp`, `Kd`), converting DeepMimic's y-up frames to z-up. A joint's
/// torque limit is `TorqueLim`, or for a spherical joint per axis `TorqueLimX`, `TorqueLimY`,
/// `TorqueLimZ` (arpspoof/Jump's jumper). Throws base::UserError naming the file, joint and field.
ModelPtr load_deepmimic(const std::filesystem::path& character, const std::filesystem::path& controller = {});

}  // namespace podium::sim
