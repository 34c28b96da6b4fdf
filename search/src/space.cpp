#include "podium/search/space.h"

#include <cmath>

#include "podium/base/error.h"
#include "podium/search/search.h"

namespace podium::search {

using base::Json;
using base::UserError;

namespace {
double number_at(const Json& j, const char* key, const std::string& path) {
  if (!j.contains(key)) throw UserError(path + "." + key + ": missing");
  if (!j[key].is_number()) throw UserError(path + "." + key + ": " + j[key].dump() + " is not a number");
  const double v = j[key].get<double>();
  if (!std::isfinite(v)) throw UserError(path + "." + key + ": must be finite");
  return v;
}
std::string name_at(const Json& j, const std::string& path) {
  if (!j.contains("name") || !j["name"].is_string() || j["name"].get<std::string>().empty())
    throw UserError(path + ".name: missing or not a non-empty string");
  return j["name"].get<std::string>();
}
}  // namespace

bool Space::contains(const std::vector<double>& x) const {
  if (x.size() != params.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!(x[i] >= params[i].low && x[i] <= params[i].high)) return false;
  return true;
}

Space Space::from_json(const Json& j, const std::string& json_path) {
  if (!j.is_array()) throw UserError(json_path + ": expected an array of parameters");
  Space space;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = base::json_path_index(json_path, i);
    Parameter p;
    p.name = name_at(j[i], path);
    p.low = number_at(j[i], "low", path);
    p.high = number_at(j[i], "high", path);
    p.integer = j[i].value("integer", false);
    if (!(p.low < p.high)) throw UserError(path + ": low " + j[i]["low"].dump() + " is not below high " + j[i]["high"].dump());
    space.params.push_back(p);
  }
  return space;
}

Json Space::to_json() const {
  Json out = Json::array();
  for (const auto& p : params) {
    Json entry = {{"name", p.name}, {"low", p.low}, {"high", p.high}};
    if (p.integer) entry["integer"] = true;
    out.push_back(entry);
  }
  return out;
}

std::vector<Feature> Feature::list_from_json(const Json& j, const std::string& json_path) {
  if (!j.is_array()) throw UserError(json_path + ": expected an array of features");
  std::vector<Feature> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = base::json_path_index(json_path, i);
    Feature f;
    f.name = name_at(j[i], path);
    f.low = number_at(j[i], "low", path);
    f.high = number_at(j[i], "high", path);
    f.unit = j[i].value("unit", "");
    if (j[i].contains("quantised") && !j[i]["quantised"].is_boolean())
      throw UserError(path + ".quantised: expected true or false, got " + j[i]["quantised"].dump());
    f.quantised = j[i].value("quantised", false);
    const std::string metric = j[i].value("metric", "euclidean");
    if (metric == "angular") f.metric = FeatureMetric::angular;
    else if (metric != "euclidean") throw UserError(path + ".metric: \"" + metric + "\" is not one of euclidean, angular");
    out.push_back(f);
  }
  return out;
}

Json Feature::list_to_json(const std::vector<Feature>& features) {
  Json out = Json::array();
  for (const auto& f : features) {
    Json entry = {{"name", f.name},
                  {"low", f.low},
                  {"high", f.high},
                  {"unit", f.unit},
                  {"metric", f.metric == FeatureMetric::angular ? "angular" : "euclidean"}};
    if (f.quantised) entry["quantised"] = true;
    out.push_back(entry);
  }
  return out;
}

}  // namespace podium::search
