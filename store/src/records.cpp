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
  t.features = Json::parse(s.text(16)).get<std::vector<double>>();
  return t;
}

}  // namespace podium::store
