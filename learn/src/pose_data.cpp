#include "podium/learn/pose_data.h"

#include "podium/base/error.h"

namespace podium::learn {

void PoseDataset::append(const PoseDataset& other) {
  if (other.dof_names != dof_names || other.condition_names != condition_names)
    throw base::UserError("pose dataset: cannot append a dataset with other DoFs or conditions");
  poses.insert(poses.end(), other.poses.begin(), other.poses.end());
  conditions.insert(conditions.end(), other.conditions.begin(), other.conditions.end());
}

PoseDataset read_pose_dataset(const std::filesystem::path& path) {
  const base::Json j = base::read_json_file(path);
  const std::string where = path.string();
  PoseDataset d;
  try {
    d.dof_names = j.at("dof_names").get<std::vector<std::string>>();
    d.lower = j.at("lower").get<std::vector<double>>();
    d.upper = j.at("upper").get<std::vector<double>>();
    d.condition_names = j.value("condition_names", std::vector<std::string>{});
    d.poses = j.at("poses").get<std::vector<std::vector<double>>>();
    d.conditions = j.value("conditions", std::vector<std::vector<double>>{});
  } catch (const base::Json::exception& e) {
    throw base::UserError(where + ": " + e.what());
  }
  const std::size_t n = d.dof_names.size();
  if (d.lower.size() != n || d.upper.size() != n)
    throw base::UserError(where + ": lower/upper have " + std::to_string(d.lower.size()) + "/" + std::to_string(d.upper.size()) +
                          " entries but dof_names has " + std::to_string(n));
  for (std::size_t k = 0; k < n; ++k)
    if (!(d.lower[k] < d.upper[k]))
      throw base::UserError(where + ": " + d.dof_names[k] + ": limits [" + std::to_string(d.lower[k]) + ", " +
                            std::to_string(d.upper[k]) + "] are not an interval");
  for (std::size_t i = 0; i < d.poses.size(); ++i)
    if (d.poses[i].size() != n)
      throw base::UserError(where + ": poses[" + std::to_string(i) + "] has " + std::to_string(d.poses[i].size()) +
                            " values, expected " + std::to_string(n));
  if (!d.condition_names.empty() && d.conditions.size() != d.poses.size())
    throw base::UserError(where + ": " + std::to_string(d.conditions.size()) + " conditions for " +
                          std::to_string(d.poses.size()) + " poses");
  for (std::size_t i = 0; i < d.conditions.size(); ++i)
    if (d.conditions[i].size() != d.condition_names.size())
      throw base::UserError(where + ": conditions[" + std::to_string(i) + "] has " + std::to_string(d.conditions[i].size()) +
                            " values, expected " + std::to_string(d.condition_names.size()));
  return d;
}

}  // namespace podium::learn
