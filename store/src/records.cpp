#include "records.h"

namespace podium::store {

Json parse_json(const std::string& text) { return text.empty() ? Json(nullptr) : Json::parse(text); }

namespace {

// The columns of kTrialSelect into either trial shape; `json_column` reads a JSON column as the
// shape's JSON type (parsed, or passed through as text).
template <class Trial, class JsonColumn>
Trial read_trial_columns(const Statement& s, JsonColumn json_column) {
  Trial t;
  t.id = s.int64(0);
  t.stage_id = s.int64(1);
  t.index = s.int64(2);
  t.params = json_column(3);
  t.context = json_column(4);
  t.info = json_column(5);
  t.seed = static_cast<std::uint64_t>(s.int64(6));
  t.state = s.text(7);
  t.attempts = static_cast<int>(s.int64(8));
  t.objectives = json_column(9);
  t.result_info = json_column(10);
  if (!s.is_null(11)) t.strategy = s.int64(11);
  t.error = s.text(12);
  t.created_at = s.real(13);
  t.started_at = s.real(14);
  t.finished_at = s.real(15);
  return t;
}

}  // namespace

TrialRecord read_trial(const Statement& s) {
  return read_trial_columns<TrialRecord>(s, [&](int column) { return parse_json(s.text(column)); });  // NULL reads as ""
}

TrialText read_trial_text(const Statement& s) {
  return read_trial_columns<TrialText>(s, [&](int column) {
    std::string text = s.text(column);
    return text.empty() ? std::string("null") : text;  // NULL reads as ""
  });
}

std::vector<double> read_features(Statement& features, std::int64_t trial_id) {
  features.reset();
  features.bind(1, trial_id);
  std::vector<double> out;
  while (features.step()) out.push_back(features.real(0));
  return out;
}

void add_to_counts(TrialCounts& c, const std::string& state, std::int64_t n) {
  c.total += n;
  if (state == "pending") c.pending += n;
  else if (state == "running") c.running += n;
  else if (state == "done") c.done += n;
  else if (state == "failed") c.failed += n;
  else if (state == "interrupted") c.interrupted += n;
  else if (state == "cancelled") c.cancelled += n;
}

}  // namespace podium::store
