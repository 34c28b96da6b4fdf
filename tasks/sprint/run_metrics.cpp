// The Acceleration + Top Speed stage's per-episode measures (sprint seed §3.2).
#include "run_metrics.h"

#include <cstddef>

#include "podium/base/error.h"
#include "track.h"

namespace podium::tasks::sprint {

std::optional<double> rise_distance(const std::vector<double>& x_m, const std::vector<double>& lean_rad, double threshold_rad) {
  if (x_m.size() != lean_rad.size())
    throw base::UserError("rise distance: " + std::to_string(x_m.size()) + " positions but " + std::to_string(lean_rad.size()) +
                          " leans");
  std::optional<double> rise;
  for (std::size_t i = 0; i < x_m.size(); ++i) {
    if (lean_rad[i] >= threshold_rad) rise.reset();
    else if (!rise) rise = x_m[i];
  }
  return rise;
}

bool flight_in_every_stride(const std::vector<double>& x_m, const std::vector<FootContacts>& contacts, double from_x_m) {
  if (x_m.size() != contacts.size())
    throw base::UserError("flight check: " + std::to_string(x_m.size()) + " positions but " + std::to_string(contacts.size()) +
                          " contact samples");
  std::vector<std::size_t> touchdowns;
  for (std::size_t i = 1; i < contacts.size(); ++i)
    if ((contacts[i].left && !contacts[i - 1].left) || (contacts[i].right && !contacts[i - 1].right)) touchdowns.push_back(i);
  int strides = 0;
  for (std::size_t k = 0; k + 1 < touchdowns.size(); ++k) {
    if (x_m[touchdowns[k]] < from_x_m) continue;
    bool flight = false;
    for (std::size_t i = touchdowns[k]; i < touchdowns[k + 1] && !flight; ++i) flight = !contacts[i].left && !contacts[i].right;
    if (!flight) return false;
    ++strides;
  }
  return strides > 0;
}

std::optional<double> segment_speed(const std::vector<double>& t_s, const std::vector<double>& x_m, double from_x_m,
                                    double to_x_m, bool to_end) {
  std::optional<double> t_from, t_to;
  for (std::size_t i = 0; i < x_m.size(); ++i) {
    const std::size_t j = i > 0 ? i - 1 : 0;
    if (!t_from) t_from = crossing_time(t_s[j], x_m[j], t_s[i], x_m[i], from_x_m);
    if (t_from && !t_to) t_to = crossing_time(t_s[j], x_m[j], t_s[i], x_m[i], to_x_m);
  }
  if (!t_from) return std::nullopt;
  double to = to_x_m;
  if (!t_to) {
    if (!to_end || x_m.back() <= from_x_m) return std::nullopt;
    t_to = t_s.back(), to = x_m.back();
  }
  if (*t_to <= *t_from) return std::nullopt;
  return (to - from_x_m) / (*t_to - *t_from);
}

}  // namespace podium::tasks::sprint
