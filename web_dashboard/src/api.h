#pragma once
// The JSON API's documents, built from store queries (no SQL here, no HTTP types either).
// Endpoints and fields are documented in the top-level README, "The dashboard".
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "podium/base/json.h"
#include "podium/store/queries.h"

namespace podium::web_dashboard {

using base::Json;

/// A request the API refuses: HTTP status and a one-line reason.
struct HttpError : std::runtime_error {
  HttpError(int status, const std::string& message) : std::runtime_error(message), status(status) {}
  int status;
};

Json campaign_list(const store::Queries& q, double now_unix_s);
/// `campaign` is an id or a name (the newest campaign of that name); 404 if none.
std::int64_t resolve_campaign(const store::Queries& q, const std::string& campaign);
Json campaign_detail(const store::Queries& q, std::int64_t campaign_id, double now_unix_s);
/// JSON text: the trials' stored JSON columns are copied into the page, not parsed.
std::string trial_page(const store::Queries& q, std::int64_t campaign_id, const store::TrialFilter& filter);
/// JSON text (written directly: 5,000 points are 40,000 numbers).
std::string scatter_points(const store::Queries& q, std::int64_t campaign_id, std::int64_t max_points);
Json strategy_table(const store::Queries& q, std::int64_t campaign_id);
/// Campaign summaries (store::campaign_summary: a walk of every done trial, ~0.1 s at 100,000),
/// each kept while its campaign's store::Store::summary_token (a few count rows) is unchanged: a
/// commit to another campaign, an event or a poll leaves it valid, unlike the response cache's
/// database-wide data_version. The token is read before the summary is made, so a kept summary is
/// never older than its token. Thread-safe; summaries of one campaign may be made twice at once.
class SummaryCache {
 public:
  /// `enabled` false: every get() makes the summary (ServeOptions::cache off, for benchmarks).
  explicit SummaryCache(bool enabled = true) : enabled_(enabled) {}
  std::shared_ptr<const Json> get(const store::Queries& q, std::int64_t campaign_id);

 private:
  bool enabled_;
  static constexpr std::size_t kMaxCampaigns = 64;  // beyond it the cache starts over
  std::mutex mutex_;
  std::map<std::int64_t, std::pair<std::string, std::shared_ptr<const Json>>> entries_;
};

/// The campaign's summary: store::campaign_summary's JSON (store/summary.h), what
/// `podium summary --json` prints.
Json summary_document(const store::Queries& q, SummaryCache& cache, std::int64_t campaign_id);
/// Several campaigns side by side: store::compare_campaigns's JSON. `campaigns`: ids or
/// names, comma-separated, 1 to 8 of them; 400 otherwise, 404 for one that does not exist.
Json comparison_document(const store::Queries& q, SummaryCache& cache, const std::string& campaigns);
Json campaign_events(const store::Queries& q, std::int64_t campaign_id, std::size_t last_n);
Json trial_detail(const store::Queries& q, std::int64_t trial_id);
Json metric_series(const store::Queries& q, std::int64_t trial_id, std::int64_t max_points,
                   const std::optional<std::string>& name);

/// The file of a trial's artifact number `index`, if it lies inside the campaign's run folder
/// (resolving symlinks and ".."); 404 for an unknown trial or artifact, 403 outside the folder.
std::filesystem::path artifact_file(const store::Queries& q, const std::filesystem::path& database, std::int64_t trial_id,
                                    std::size_t index);
/// The name the trial's artifact number `index` downloads as: "<campaign>_<stage>-<index>_<artifact><ext>".
std::string artifact_download_name(const store::Queries& q, std::int64_t trial_id, std::size_t index);
/// The trial's log (store::kTrialLog in its folder), under the same rule; 404 while it has none.
std::filesystem::path trial_log_file(const store::Queries& q, const std::filesystem::path& database, std::int64_t trial_id);
/// The index of the trial's artifact called `name`; 404 if it has none.
std::size_t artifact_index(const store::Queries& q, std::int64_t trial_id, const std::string& name);
/// The trial's style curves: its artifact `curves` (tasks/getup_curves/README.md: per recorded
/// episode its curve — name, T, control points — and the target and achieved h, θ_x, θ_z at
/// control rate), parsed and checked (every series as long as its time axis), under
/// artifact_file's rule. 404 without one; 500 naming the file, the JSON path and the value for a
/// malformed one.
Json style_curves_document(const store::Queries& q, const std::filesystem::path& database, std::int64_t trial_id);

}  // namespace podium::web_dashboard
