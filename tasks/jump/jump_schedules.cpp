#include "jump_schedules.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"

namespace podium::tasks::jump {

JumpKind parse_jump_kind(const std::string& name, const std::string& where) {
  if (name == "high_jump") return JumpKind::high_jump;
  if (name == "obstacle") return JumpKind::obstacle;
  throw base::UserError(where + ": \"" + name + "\" is not one of high_jump, obstacle");
}

const char* jump_kind_name(JumpKind kind) { return kind == JumpKind::high_jump ? "high_jump" : "obstacle"; }

double difficulty_ratio(JumpKind kind, double z_m) { return kind == JumpKind::high_jump ? 2.0 * z_m - 1.0 : z_m; }

double control_hz_for(double rho, double sim_hz) {
  if (!(sim_hz >= 30.0) || sim_hz != std::round(sim_hz) || sim_hz > 1e6)
    throw base::UserError("jump: sim_hz " + std::to_string(sim_hz) + " is not a whole number of Hz in [30, 1e6]");
  const double f = 10.0 + 20.0 * std::clamp(rho, 0.0, 1.0);
  const auto hz = static_cast<long>(sim_hz);
  long best = 1;
  for (long d = 1; d <= hz; ++d)
    if (hz % d == 0 && std::abs(static_cast<double>(d) - f) < std::abs(static_cast<double>(best) - f)) best = d;
  return static_cast<double>(best);
}

double offset_coefficient(double rho) { return 48.0 - 33.0 * std::clamp(rho, 0.0, 1.0); }

character::ThresholdCurriculum::Config difficulty_curriculum(JumpKind kind) {
  character::ThresholdCurriculum::Config c;
  c.factor = 1.0;
  c.accumulate = true;
  if (kind == JumpKind::high_jump) {
    c.initial = 0.50, c.increment = 0.01, c.threshold = 30.0, c.limit = 2.00;
  } else {
    c.initial = 0.05, c.increment = 0.05, c.threshold = 50.0, c.limit = 2.50;
  }
  return c;
}

}  // namespace podium::tasks::jump
