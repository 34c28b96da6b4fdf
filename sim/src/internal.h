#pragma once
// Passes shared by the dynamics files (not public API).
#include <functional>

#include "podium/sim/data.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/model.h"

namespace podium::sim::internal {

void velocity_pass(const CharacterModel& model, CharacterData& data);
/// mass_matrix for data whose link poses already match data.q.
void mass_matrix_posed(const CharacterModel& model, CharacterData& data);
/// bias_forces for posed data (runs velocity_pass).
void bias_forces_posed(const CharacterModel& model, CharacterData& data);
/// SPD spring-damper term Q (thesis eq. 2.20) into data.Q; root entries 0.
void spd_spring_term(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                     double dt_s);
/// stable_pd_maba for data whose link poses already match data.q (forward_kinematics done).
void stable_pd_maba_posed(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                          double dt_s);

/// tau += Jᵀ force: the generalized force of a world force (N) at a world point fixed to `link`
/// (also a constraint row's Jacobian, for a unit direction). Needs forward_kinematics.
void add_point_force(const CharacterModel& model, const CharacterData& data, int link, const Eigen::Vector3d& point,
                     const Eigen::Vector3d& force, Eigen::Ref<Eigen::VectorXd> tau);

/// Calls visit(link, geom, geom_point, surface_point, distance) for each point of the model's geoms
/// that can touch the plane n·x = 0 first: a sphere's centre, both ends of a capsule's axis, a
/// box's corners; `surface_point` is the geom's point nearest the plane, `distance` its height
/// above it (negative: below). `geom_point` numbers these points in model order. Needs
/// forward_kinematics.
void for_each_plane_point(const CharacterModel& model, const CharacterData& data, const Eigen::Vector3d& normal,
                          const std::function<void(int link, const Geom& geom, int geom_point,
                                                   const Eigen::Vector3d& surface_point, double distance)>& visit);

}  // namespace podium::sim::internal
