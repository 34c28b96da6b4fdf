// The sprint's track: finish-plane crossing, lane and fall rules (sprint seed §2, §3.1).
#include "track.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "podium/base/error.h"

namespace podium::tasks::sprint {

double body_front_x(const sim::CharacterModel& model, const sim::CharacterData& data, int body) {
  if (body < 0 || body >= static_cast<int>(model.bodies().size()))
    throw base::UserError("sprint: body " + std::to_string(body) + " is not a body of model " + model.name());
  const int link = model.bodies()[body].link;
  const sim::LinkData& d = data.links[link];
  double front = -std::numeric_limits<double>::infinity();
  for (const sim::Geom& g : model.links()[link].geoms) {
    if (g.body != body) continue;
    const Eigen::Vector3d c = d.p + d.R * g.pos;
    const Eigen::Matrix3d R = d.R * g.rot.toRotationMatrix();
    double reach = 0.0;  // the support of the shape in +x, from its centre
    switch (g.type) {
      case sim::ShapeType::sphere:
        reach = g.radius;
        break;
      case sim::ShapeType::capsule:  // the segment along the local z axis, swept by the radius
        reach = g.half_length * std::abs(R(0, 2)) + g.radius;
        break;
      case sim::ShapeType::box:
        reach = R.row(0).cwiseAbs().dot(g.half_extents);
        break;
    }
    front = std::max(front, c.x() + reach);
  }
  if (!std::isfinite(front))
    throw base::UserError("sprint: body " + model.bodies()[body].name + " of model " + model.name() + " has no geoms");
  return front;
}

std::optional<double> crossing_time(double t0, double x0, double t1, double x1, double plane) {
  if (x0 >= plane) return t0;
  if (x1 < plane) return std::nullopt;
  return t0 + (t1 - t0) * (plane - x0) / (x1 - x0);  // x1 > x0 here: linear within the step
}

FinishLine::FinishLine(const sim::CharacterModel& model, const TrackSpec& track) : model_(&model), track_(track) {
  torso_.push_back(0);
  if (model.torso_body() != 0) torso_.push_back(model.torso_body());
}

double FinishLine::torso_front(const sim::World& world) const {
  double front = -std::numeric_limits<double>::infinity();
  for (const int b : torso_) front = std::max(front, body_front_x(*model_, world.data(), b));
  return front;
}

void FinishLine::reset(const sim::World& world) {
  finish_.reset();
  last_t_ = world.time_s();
  last_x_ = torso_front(world);
  if (last_x_ >= track_.length_m) finish_ = last_t_;
}

void FinishLine::observe(const sim::World& world) {
  if (finish_) return;
  const double t = world.time_s(), x = torso_front(world);
  finish_ = crossing_time(last_t_, last_x_, t, x, track_.length_m);
  last_t_ = t;
  last_x_ = x;
}

base::Json FinishLine::state() const {
  return {{"last_t", last_t_}, {"last_x", last_x_}, {"finish", finish_ ? base::Json(*finish_) : base::Json(nullptr)}};
}

void FinishLine::load_state(const base::Json& state) {
  try {
    last_t_ = state.at("last_t").get<double>();
    last_x_ = state.at("last_x").get<double>();
    const base::Json& f = state.at("finish");
    if (f.is_null()) finish_.reset();
    else finish_ = f.get<double>();
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("sprint: finish line state: ") + e.what());
  }
}

bool outside_lane(const TrackSpec& track, double y_m) { return std::abs(y_m - track.lane_centre_y_m) > 0.5 * track.lane_width_m; }

int body_outside_lane(const TrackSpec& track, const sim::World& world, std::span<const int> bodies) {
  for (const int b : bodies)
    if (outside_lane(track, world.body_centroid(b).y())) return b;
  return -1;
}

int fallen_body(const sim::Observation& observation, const GroundAllowance& allowed, bool first_step_taken) {
  auto listed = [](const std::vector<int>& bodies, int b) { return std::find(bodies.begin(), bodies.end(), b) != bodies.end(); };
  for (const sim::Contact& c : observation.contacts) {
    if (c.partner != sim::Contact::Partner::ground) continue;
    if (listed(allowed.feet, c.body)) continue;
    if (!first_step_taken && listed(allowed.hands, c.body)) continue;
    return c.body;
  }
  return -1;
}

SprintBodies SprintBodies::of(const sim::CharacterModel& model) {
  auto find = [&](const char* name) {
    const int b = model.find_body(name);
    if (b < 0) throw base::UserError(std::string("sprint: model ") + model.name() + " has no body " + name);
    return b;
  };
  SprintBodies s;
  s.left_foot = find("left_foot");
  s.right_foot = find("right_foot");
  s.left_hand = find("left_hand");
  s.right_hand = find("right_hand");
  s.left_thigh = find("left_thigh");
  s.right_thigh = find("right_thigh");
  s.left_upper_arm = find("left_upper_arm");
  s.right_upper_arm = find("right_upper_arm");
  return s;
}

}  // namespace podium::tasks::sprint
