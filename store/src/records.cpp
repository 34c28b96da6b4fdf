#include "records.h"

namespace podium::store {

Json parse_json(const std::string& text) { return text.empty() ? Json(nullptr) : Json::parse(text); }

TrialRecord read_trial(const Statement& s) {
  TrialRecord t;
  t.id = s.int64(0);
  t.stage_id = s.int64(1);
  t.index = s.int64(2);
  t.params = parse_json(s.text(3));
  t.context = parse_json(s.text(4));
  t.info = parse_json(s.text(5));
  t.seed = static_cast<std::uint64_t>(s.int64(6));
  t.state = s.text(7);
  t.attempts = static_cast<int>(s.int64(8));
  t.objectives = s.is_null(9) ? Json(nullptr) : parse_json(s.text(9));
  t.result_info = s.is_null(10) ? Json(nullptr) : parse_json(s.text(10));
  if (!s.is_null(11)) t.strategy = s.int64(11);
  t.error = s.text(12);
  t.created_at = s.real(13);
  t.started_at = s.real(14);
  t.finished_at = s.real(15);
  return t;
}

TrialText read_trial_text(const Statement& s) {
  const auto json_text = [&](int column) {
    std::string text = s.text(column);
    return text.empty() ? std::string("null") : text;  // NULL reads as ""
  };
  TrialText t;
  t.id = s.int64(0);
  t.stage_id = s.int64(1);
  t.index = s.int64(2);
  t.params = json_text(3);
  t.context = json_text(4);
  t.info = json_text(5);
  t.seed = static_cast<std::uint64_t>(s.int64(6));
  t.state = s.text(7);
  t.attempts = static_cast<int>(s.int64(8));
  t.objectives = json_text(9);
  t.result_info = json_text(10);
  if (!s.is_null(11)) t.strategy = s.int64(11);
  t.error = s.text(12);
  t.created_at = s.real(13);
  t.started_at = s.real(14);
  t.finished_at = s.real(15);
  return t;
}

std::vector<double> read_features(Statement& features, std::int64_t trial_id) {
  features.reset();
  features.bind(1, trial_id);
  std::vector<double> out;
  while (features.step()) out.push_back(features.real(0));
  return out;
}

}  // namespace podium::store
