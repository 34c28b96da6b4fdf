#include "podium/character/training_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <stdexcept>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/learn/training_checkpoint.h"
#include "podium/learn/wall_budget.h"

namespace podium::character {

using base::Json;
namespace fs = std::filesystem;

double figure(const Figures& figures, const std::string& name) {
  const auto it = figures.find(name);
  if (it == figures.end()) throw std::logic_error("training stage: the test reported no figure \"" + name + "\"");
  return it->second;
}

std::optional<ExportReason> best_by(const ExportRecord& tested, const ExportRecord* exported,
                                    const std::vector<RankBy>& ranking) {
  if (!exported) return ExportReason::best;
  for (const RankBy& r : ranking) {
    const double t = figure(tested.figures, r.name), e = figure(exported->figures, r.name);
    if (t == e) continue;
    if ((t > e) == r.higher_is_better) return ExportReason::best;
    return std::nullopt;
  }
  return std::nullopt;
}

std::string to_string(ExportReason reason) {
  switch (reason) {
    case ExportReason::passed:
      return "passed";
    case ExportReason::best:
      return "best";
    case ExportReason::last:
      return "last";
  }
  return "?";
}

Json ExportRecord::to_json() const {
  return {{"reason", to_string(reason)}, {"test", test}, {"env_steps", env_steps}, {"figures", figures}};
}

ExportRecord ExportRecord::from_json(const Json& json) {
  ExportRecord r;
  const std::string reason = json.at("reason").get<std::string>();
  if (reason == "passed") r.reason = ExportReason::passed;
  else if (reason == "best") r.reason = ExportReason::best;
  else if (reason == "last") r.reason = ExportReason::last;
  else throw base::UserError("training stage: export reason \"" + reason + "\" is not passed, best or last");
  r.test = json.at("test").get<int>();
  r.env_steps = json.at("env_steps").get<std::int64_t>();
  r.figures = json.at("figures").get<Figures>();
  return r;
}

double TrainingTally::mean_return() const {
  return episodes > 0 ? return_sum / static_cast<double>(episodes) : std::numeric_limits<double>::quiet_NaN();
}

double TestRound::seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); }

Json time_metric_entries() {
  const auto entry = [](const char* name, const char* description) {
    // plugins::metric_entry's shape (character/ does not depend on plugins/): a learning curve
    // over environment steps.
    return Json{{"name", name},
                {"unit", "s"},
                {"description", description},
                {"x", {{"name", "environment steps"}}},
                {"kind", "learning_curve"}};
  };
  const char* note = " since the previous test (wall time: differs between runs of a seed)";
  return {entry("time/rollout_s", (std::string("seconds stepping the copies and querying the policy") + note).c_str()),
          entry("time/update_s", (std::string("seconds in network updates") + note).c_str()),
          entry("time/test_s", "seconds of the test at this step (wall time: differs between runs of a seed)"),
          entry("time/wall_s", (std::string("wall seconds of training, tests, exports and checkpoints") + note).c_str())};
}

namespace {

// The checkpoint files of a trial folder: training.ckpt, or for a stage that tags its copies
// training_<tag>.ckpt with training_<tag>.json beside it ({"order", "build"}: the copies' build
// state, and the order of the tags, so the newest file is found again).
class CheckpointFiles {
 public:
  explicit CheckpointFiles(fs::path dir) : dir_(std::move(dir)) {}

  static std::string stem(const std::string& tag) { return tag.empty() ? "training" : "training_" + tag; }
  fs::path file(const std::string& tag) const { return dir_ / (stem(tag) + ".ckpt"); }
  fs::path side(const std::string& tag) const { return dir_ / (stem(tag) + ".json"); }

  struct Newest {
    std::string tag;
    Json build;
  };
  // The tagged checkpoint to resume from: of the files with a side file, the last tagged.
  std::optional<Newest> newest_tagged() const {
    static const std::regex name(R"(training_(.+)\.ckpt)");
    std::optional<Newest> best;
    std::int64_t best_order = -1;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      std::smatch m;
      const std::string file = entry.path().filename().string();
      if (!std::regex_match(file, m, name) || !fs::exists(side(m[1]))) continue;
      const Json saved = base::read_json_file(side(m[1]));
      if (saved.value("format", Json()) != learn::TrainingCheckpoint::kFormatVersion)
        throw base::UserError(
            "training stage: " + side(m[1]).string() + " is of another format than this build's " +
            std::to_string(learn::TrainingCheckpoint::kFormatVersion) +
            ": delete the trial's training_* files to train it from scratch, or finish it with the build that wrote them");
      if (const auto order = saved.at("order").get<std::int64_t>(); order > best_order)
        best_order = order, best = Newest{m[1], saved.at("build")};
    }
    if (best) order_ = best_order;
    return best;
  }
  // Names the copies now checkpointed under `tag`.
  void note(const std::string& tag, const Json& build) {
    ++order_;
    base::write_json_file_atomic(side(tag),
                                 {{"format", learn::TrainingCheckpoint::kFormatVersion}, {"order", order_}, {"build", build}});
  }
  // After the first save under `tag`: the older tags' files go.
  void remove_others(const std::string& tag) const {
    static const std::regex name(R"(training_(.+)\.(ckpt|json))");
    for (const auto& entry : fs::directory_iterator(dir_)) {
      std::smatch m;
      const std::string file = entry.path().filename().string();
      if (std::regex_match(file, m, name) && m[1] != tag) fs::remove(entry.path());
    }
  }

 private:
  fs::path dir_;
  mutable std::int64_t order_ = -1;
};

// What the driver keeps in the checkpoint's extra, beside the stage's state.
struct DriverState {
  std::optional<ExportRecord> exported;
  std::optional<ExportRecord> last_test;  // the last test's figures (reason unused)
  int tests = 0;
  Json clock;
  std::string warm_start;

  Json to_json(const Json& stage) const {
    return {{"stage", stage},
            {"exported", exported ? exported->to_json() : Json()},
            {"last_test", last_test ? last_test->to_json() : Json()},
            {"tests", tests},
            {"clock", clock},
            {"warm_start", warm_start}};
  }
  static DriverState from_json(const Json& j) {
    DriverState s;
    if (!j.at("exported").is_null()) s.exported = ExportRecord::from_json(j.at("exported"));
    if (!j.at("last_test").is_null()) s.last_test = ExportRecord::from_json(j.at("last_test"));
    s.tests = j.at("tests").get<int>();
    s.clock = j.at("clock");
    s.warm_start = j.at("warm_start").get<std::string>();
    return s;
  }
};

void check(const StageSettings& s) {
  const auto fail = [&](const std::string& what) { throw std::logic_error("training stage " + s.name + ": " + what); };
  if (s.total_steps < 1) fail("total_steps " + std::to_string(s.total_steps) + " is not ≥ 1");
  if (s.steps_per_iteration < 1) fail("steps_per_iteration is not ≥ 1");
  if (s.test_every < 1) fail("test_every is not ≥ 1");
  if (s.checkpoint_every < 1) fail("checkpoint_every is not ≥ 1");
}

// One run of a stage: the loop's parts, each a member function.
class Driver {
 public:
  Driver(TrainingStage& stage, const StageSettings& settings, const StageRun& run)
      : stage_(stage),
        s_(settings),
        run_(run),
        files_(run.work_dir),
        checkpoint_(files_.file(""), settings.checkpoint_every, run.report.metric) {
    send_ = [this](const std::string& name, double step, double value) { checkpoint_.metric(name, step, value); };
  }

  StageOutcome run() {
    check(s_);
    const bool resumed = start();
    learn::WallBudget clock(s_.train_minutes, state_.clock);
    stage_.begin(resumed, *learner_);
    round_start_ = std::chrono::steady_clock::now();
    if (!resumed && s_.test_before_training) test(0);
    progress(clock);
    std::string stopped_by = "steps";
    while (learner_->env_steps() < s_.total_steps) {
      if (stage_.finished()) {
        stopped_by = "schedule";
        break;
      }
      if (!clock.another_round_fits()) {
        stopped_by = "time";
        break;
      }
      iterate(clock);
    }
    base::log_info(clock.end_message(s_.name, learner_->env_steps(), s_.total_steps));
    return finish(stopped_by);
  }

 private:
  // Builds the copies and the learner, then resumes or warm-starts; returns whether it resumed.
  bool start() {
    fs::create_directories(run_.work_dir);
    const std::optional<CheckpointFiles::Newest> saved = files_.newest_tagged();
    stage_.build(saved ? saved->build : Json());
    tag_ = stage_.checkpoint_tag();
    checkpoint_.retarget(files_.file(tag_));
    learner_ = learn::make_learner(stage_.learner_spec(), stage_.envs().observation_space(), stage_.envs().action_space(),
                                   base::derive_seed(run_.seed, 2));
    const bool checkpoint_warm_start = !s_.warm_start.empty() && s_.warm_start_kind == StageSettings::WarmStart::checkpoint;
    if (checkpoint_warm_start) {
      if (!tag_.empty())
        throw std::logic_error("training stage " + s_.name + ": a checkpoint warm start needs an untagged checkpoint");
      checkpoint_.start_from(s_.warm_start);
    }
    std::optional<Json> extra = checkpoint_.resume(*learner_, stage_.envs());
    if (extra) {
      state_ = DriverState::from_json(*extra);
      stage_.load_state(extra->at("stage"));
    } else if (!tag_.empty()) {
      files_.note(tag_, stage_.build_state());
    }
    // Until this trial's first save, its checkpoint is the warm start's source's (also after a
    // kill before that save): the source's export record and clock do not carry over.
    if (checkpoint_warm_start && state_.warm_start != s_.warm_start.string()) {
      state_.exported.reset();
      state_.clock = nullptr;
      state_.warm_start = s_.warm_start.string();
      return false;
    }
    if (extra) {
      base::log_info(s_.name + ": resumes after update " + std::to_string(checkpoint_.updates()) + " (environment step " +
                     std::to_string(learner_->env_steps()) + ")");
      return true;
    }
    if (!s_.warm_start.empty() && !checkpoint_warm_start) {  // a policy
      learner_->warm_start(s_.warm_start);
      state_.warm_start = s_.warm_start.string();
    }
    return false;
  }

  void check_cancel() const {
    if (run_.cancel && run_.cancel->load())
      throw std::runtime_error(s_.name + ": cancelled at environment step " + std::to_string(learner_->env_steps()));
  }

  // One iteration: train, the stage's per-iteration hook, a test when one is due, a checkpoint.
  void iterate(learn::WallBudget& clock) {
    check_cancel();
    clock.start_round();
    Iteration it;
    it.index = checkpoint_.updates() + 1;
    it.env_steps_before = learner_->env_steps();
    learner_->train_until(stage_.envs(), it.env_steps_before + s_.steps_per_iteration, [&](const learn::TrainStats& t) {
      check_cancel();
      add(it.training, t);
      add(since_test_, t);
    });
    it.env_steps = learner_->env_steps();
    stage_.on_iteration(it, *learner_, send_);
    if (const std::string tag = stage_.checkpoint_tag(); tag != tag_) {
      tag_ = tag;
      checkpoint_.retarget(files_.file(tag_));
      files_.note(tag_, stage_.build_state());
    }
    if (it.index % s_.test_every == 0) test(it.index);
    clock.end_round();
    state_.clock = clock.state();
    progress(clock);
    if (checkpoint_.on_update(*learner_, stage_.envs(), state_.to_json(stage_.state())) && !tag_.empty())
      files_.remove_others(tag_);
  }

  static void add(TrainingTally& tally, const learn::TrainStats& t) {
    tally.last = t;
    if (t.episodes > 0) tally.return_sum += t.mean_return * static_cast<double>(t.episodes), tally.episodes += t.episodes;
    tally.rollout_s += t.rollout_seconds, tally.update_s += t.update_seconds;
  }

  // A test: the stage's statistic and metrics, the time/ series, the export rule.
  void test(std::int64_t iteration) {
    TestRound round;
    round.test = iteration == 0 ? 0 : state_.tests + 1;
    round.iteration = iteration;
    round.env_steps = learner_->env_steps();
    round.training = since_test_;
    round.started = std::chrono::steady_clock::now();
    ExportRecord tested;
    tested.figures = stage_.test(round, *learner_, send_);
    tested.test = round.test;
    tested.env_steps = round.env_steps;
    const double test_s = round.seconds();
    state_.tests = round.test;
    state_.last_test = tested;
    if (const auto reason = stage_.export_rule(tested, state_.exported ? &*state_.exported : nullptr)) {
      tested.reason = *reason;
      learner_->export_torchscript(policy_file());
      state_.exported = tested;
    }
    if (iteration > 0) {
      const auto step = static_cast<double>(round.env_steps);
      send_("time/rollout_s", step, since_test_.rollout_s);
      send_("time/update_s", step, since_test_.update_s);
      send_("time/test_s", step, test_s);
      send_("time/wall_s", step, std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start_).count());
    }
    since_test_ = {};
    round_start_ = std::chrono::steady_clock::now();
  }

  void progress(const learn::WallBudget& clock) const {
    if (!run_.report.progress) return;
    const double steps = static_cast<double>(learner_->env_steps()) / static_cast<double>(s_.total_steps);
    run_.report.progress(std::min(1.0, std::max({steps, clock.fraction_used(), stage_.progress()})));
  }

  fs::path policy_file() const { return run_.work_dir / "policy.pt"; }

  // The final export (when no test exported one) and the recording of the exported policy.
  StageOutcome finish(const std::string& stopped_by) {
    StageOutcome out;
    out.policy = policy_file();
    out.env_steps = learner_->env_steps();
    out.iterations = checkpoint_.updates();
    out.tests = state_.tests;
    out.stopped_by = stopped_by;
    if (!state_.exported) {
      ExportRecord last = state_.last_test.value_or(ExportRecord{});
      last.reason = ExportReason::last;
      last.env_steps = out.env_steps;
      learner_->export_torchscript(out.policy);
      state_.exported = last;
    }
    out.exported = *state_.exported;
    const learn::FrozenPolicy policy(out.policy);
    stage_.record({out.exported, out.policy, policy, *learner_, send_, run_.work_dir / "rollouts"});
    if (run_.report.progress) run_.report.progress(1.0);
    return out;
  }

  TrainingStage& stage_;
  const StageSettings& s_;
  const StageRun& run_;
  CheckpointFiles files_;
  learn::TrainingCheckpoint checkpoint_;
  MetricFn send_;
  std::unique_ptr<learn::Learner> learner_;
  DriverState state_;
  std::string tag_;
  TrainingTally since_test_;
  std::chrono::steady_clock::time_point round_start_;  // the previous test's end (time/wall_s)
};

}  // namespace

StageOutcome run_training_stage(TrainingStage& stage, const StageSettings& settings, const StageRun& run) {
  return Driver(stage, settings, run).run();
}

}  // namespace podium::character
