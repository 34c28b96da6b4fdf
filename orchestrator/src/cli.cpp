// The `podium` command line: submit, run, status, trials, log, pause, resume, cancel, extend, export,
// summary, serve, tasks, tool (and the internal `worker`). Exit codes: 0 ok, 1 runtime failure (and `run` when a
// campaign it ran ended failed), 2 usage or spec error.
#include <unistd.h>

#include <algorithm>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <vector>

#include "native_blas.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/version.h"
#include "podium/orchestrator/campaigns.h"
#include "podium/orchestrator/scheduler.h"
#include "podium/orchestrator/spec.h"
#include "podium/store/run_folders.h"
#include "podium/store/store.h"
#include "podium/store/summary.h"
#include "podium/store/writer_lock.h"
#include "podium/web_dashboard/server.h"
#include "spec_edit.h"
#include "task_listing.h"
#include "task_tools.h"
#include "trial_runner.h"
#include "worker.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using podium::base::Json;
using podium::store::Store;

namespace {

std::string error_line(const std::string& what);

constexpr const char* kUsage = R"(usage: podium <command> [options]

commands:
  submit SPEC.json [--set PATH=VALUE]...
                             validate a campaign spec (edited by --set) and queue it (prints the campaign id)
  run [--workers N] [--follow] [--log-json]
                             run queued and resumable campaigns until none is left
  status [CAMPAIGN] [--json] campaigns and their progress
  trials CAMPAIGN [--json]   the trials of a campaign
  log CAMPAIGN TRIAL [--tail N] [--path]
                             a trial's log (what its attempts wrote), e.g. podium log getup weaker/0
  pause|resume|cancel CAMPAIGN
  extend CAMPAIGN [--stage NAME] --add-trials N
                             raise a done campaign's last stage's trial budget and queue it again
  export CAMPAIGN --format csv|json [--metrics]
                             every trial, objectives and features named (--metrics: with each trial's
                             metric series, JSON only)
  summary CAMPAIGN... [--json] [--short]
                             per stage: trials done, the best trial, the strategies found, the task's
                             result tables; several campaigns: side by side, with discovery curves
  tasks [NAME] [--json] [--all] [--config JSON]
                             installed task plugins: params, features, metrics, presets, config keys
                             (--all: with the test plugins; --config: NAME described at that config)
  tool [TASK [COMMAND [ARGS...]]]
                             a task's command-line tool (alone: which tasks have one; TASK --help: its
                             commands), e.g. podium tool getup_curves edit faceup.json --out late.json
  serve [--port N] [--host H] the read-only web dashboard (default http://127.0.0.1:8080/)
  version | --version

every command but tool takes --db PATH (default ./podium.db); every command takes --help.
)";

struct Command {
  po::options_description options;
  po::positional_options_description positional;
  po::variables_map vm;
};

// Parses a subcommand's options; returns false (after printing help) when --help was given.
bool parse(Command& cmd, const std::string& name, const std::string& synopsis, int argc, char** argv) {
  cmd.options.add_options()("db", po::value<std::string>()->default_value("podium.db"), "database file")("help,h",
                                                                                                         "show this help");
  po::store(po::command_line_parser(argc, argv).options(cmd.options).positional(cmd.positional).run(), cmd.vm);
  if (cmd.vm.count("help")) {
    std::cout << "usage: podium " << name << " " << synopsis << "\n\n" << cmd.options << "\n";
    return false;
  }
  po::notify(cmd.vm);
  return true;
}

fs::path worker_binary() { return boost::dll::program_location().string(); }

std::unique_ptr<Store> open_read(const Command& cmd) {
  return Store::open(cmd.vm["db"].as<std::string>(), Store::Access::read_only);
}

std::int64_t campaign_id(const Store& store, const std::string& id_or_name) {
  return podium::store::find_campaign_id(store, id_or_name);
}

// A table column named by an objective or feature entry: "name", or "name(unit)" (one word).
std::string named_column(const Json& entry) {
  const std::string unit = entry.value("unit", std::string());
  return entry.value("name", std::string()) + (unit.empty() ? "" : "(" + unit + ")");
}

std::string fmt_time(double unix_s) {
  if (unix_s <= 0) return "-";
  const std::time_t t = static_cast<std::time_t>(unix_s);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  return buffer;
}

// `alive`: a scheduler holds the database's writer lock. Without one, a "running" campaign is
// stopped and its local attempts shown running died with the scheduler that ran them: their
// trials count as pending (`podium run` runs them again), never as running beside "stopped".
Json status_json(const Store& store, const podium::store::CampaignRecord& c, const fs::path& db, bool alive) {
  const auto counts = store.trial_counts(c.id);
  Json stages = Json::array();
  std::int64_t budget = 0, running_total = 0, interrupted_total = 0;
  for (const auto& st : store.stages(c.id)) {
    const auto sc = store.stage_trial_counts(st.id);
    budget += st.budget_trials;
    Json running = Json::array();
    std::int64_t interrupted = 0;
    // Trial indices: a read per running attempt when they are few, else the stage's trials once.
    const auto attempts = store.running_attempts(st.id);
    std::map<std::int64_t, std::int64_t> index_of;
    if (attempts.size() > 64)
      for (const auto& t : store.trials(st.id)) index_of[t.id] = t.index;
    for (const auto& a : attempts) {
      const bool dead = !alive && a.job_id.empty();
      interrupted += dead;
      if (!index_of.count(a.trial_id))
        if (const auto trial = store.trial(a.trial_id)) index_of[a.trial_id] = trial->index;
      const std::int64_t index = index_of[a.trial_id];
      running.push_back({{"name", podium::store::trial_name(st.name, index)},
                         {"trial", index},
                         {"attempt", a.number},
                         {"worker", a.worker},
                         {"host", a.host},
                         {"job_id", a.job_id},
                         {"started_at", a.started_at},
                         {"interrupted", dead}});
    }
    interrupted = std::min<std::int64_t>(interrupted, sc.running);
    running_total += sc.running - interrupted;
    interrupted_total += interrupted;
    stages.push_back({{"index", st.index},
                      {"name", st.name},
                      {"task", st.task},
                      {"algorithm", st.algorithm},
                      {"state", podium::store::shown_stage_state(c.state, st.state)},
                      {"budget_trials", st.budget_trials},
                      {"done", sc.done},
                      {"failed", sc.failed},
                      {"running", sc.running - interrupted},
                      {"pending", sc.pending + sc.interrupted + interrupted},
                      {"cancelled", sc.cancelled},
                      {"elapsed_s", st.elapsed_s},
                      {"error", st.error},
                      {"running_attempts", running},
                      {"objectives", podium::store::objective_entries(st.description)},
                      {"features", podium::store::feature_entries(st.description)}});
  }
  return {{"id", c.id},
          {"name", c.name},
          {"state", c.state},
          {"scheduler", alive ? "alive" : "none"},
          {"seed", c.seed},
          {"budget_trials", budget},
          {"done", counts.done},
          {"failed", counts.failed},
          {"running", running_total},
          {"pending", counts.pending + counts.interrupted + interrupted_total},
          {"cancelled", counts.cancelled},
          {"created_at", c.created_at},
          {"started_at", c.started_at},
          {"finished_at", c.finished_at},
          {"run_dir", podium::store::campaign_run_dir(db, c).string()},
          {"error", c.error},
          {"stages", stages}};
}

int cmd_submit(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("spec", po::value<std::string>()->required(), "campaign spec (JSON)")(
      "set", po::value<std::vector<std::string>>()->composing(),
      "PATH=VALUE: edit the spec before it is checked and stored, e.g. --set seed=29 --set "
      "'stages[0].config.total_steps=4000000' (VALUE is JSON, or a string if it does not parse)");
  cmd.positional.add("spec", 1);
  if (!parse(cmd, "submit", "SPEC.json [--set PATH=VALUE]... [--db PATH]", argc, argv)) return 0;
  const std::string file = cmd.vm["spec"].as<std::string>();
  Json spec = podium::base::read_json_file(file);
  // Errors found after the edits name the edited spec, since the value at fault may be an edit's.
  std::string source = file;
  if (cmd.vm.count("set")) {
    for (const auto& edit : cmd.vm["set"].as<std::vector<std::string>>()) podium::orchestrator::apply_spec_edit(spec, edit);
    source += " as edited by --set";
  }
  const auto id = podium::orchestrator::submit_campaign(cmd.vm["db"].as<std::string>(), spec, source,
                                                        fs::absolute(file).parent_path(), worker_binary());
  std::cout << id << "\n";
  // A name already used is not refused, but the older campaign stops answering to it.
  auto store = Store::open(cmd.vm["db"].as<std::string>(), Store::Access::read_only);
  const std::string name = store->campaign(id)->name;
  std::string older;
  for (const auto& c : store->campaigns())
    if (c.name == name && c.id != id) older += (older.empty() ? "" : ", ") + std::to_string(c.id);
  if (!older.empty())
    std::cerr << "podium: note: campaign " << id << " has the name \"" << name << "\" of campaign " << older
              << "; a CAMPAIGN name means the newest campaign of that name, so \"" << name << "\" is now campaign " << id
              << " (the older stay reachable by id)\n";
  return 0;
}

// Whether `podium run` has work: a campaign the scheduler takes up (queued, or running when a
// scheduler stopped).
bool has_runnable_campaign(const Store& store) {
  for (const auto& c : store.campaigns())
    if (c.state == "queued" || c.state == "running") return true;
  return false;
}

int cmd_run(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("workers", po::value<int>()->default_value(2), "worker processes")(
      "follow", "keep waiting for new campaigns")("log-json", "machine-readable events on stdout instead of progress");
  if (!parse(cmd, "run", "[--workers N] [--follow] [--log-json] [--db PATH]", argc, argv)) return 0;
  const int workers = cmd.vm["workers"].as<int>();
  if (workers < 1 || workers > podium::orchestrator::kMaxWorkers)
    throw podium::base::UserError("--workers: " + std::to_string(workers) + " is not in [1, " +
                                  std::to_string(podium::orchestrator::kMaxWorkers) + "]");
  podium::orchestrator::SchedulerOptions options;
  options.workers = static_cast<std::size_t>(workers);
  options.follow = cmd.vm.count("follow") > 0;
  options.log_json = cmd.vm.count("log-json") > 0;
  options.progress = !options.log_json && ::isatty(STDERR_FILENO);
  options.worker_binary = worker_binary();
  options.database = cmd.vm["db"].as<std::string>();
  if (!options.follow && !fs::exists(options.database)) {
    std::cerr << "nothing to run: no database " << options.database.string() << " (podium submit creates it)\n";
    return 0;
  }
  if (!fs::exists(options.database)) Store::open(options.database, Store::Access::read_write);  // --follow
  // One scheduler per database file, whatever path reaches it; taken before the store is opened
  // for writing, so a second one never touches the file.
  const podium::store::WriterLock lock(options.database);
  auto store = Store::open(options.database, Store::Access::read_write);
  if (!options.follow && !has_runnable_campaign(*store)) {
    std::cerr << "nothing to run: no queued or running campaign in " << options.database.string()
              << " (podium status lists them; podium resume continues a paused one)\n";
    return 0;
  }
  const double started = podium::store::now_unix_s();
  int code = podium::orchestrator::run_scheduler(*store, options);
  // Exit 1 when a campaign this run ended failed (README "Exit codes").
  for (const auto& c : store->campaigns()) {
    if (c.finished_at < started) continue;
    if (c.state == "failed" && code == 0) code = 1;
    if (options.log_json) continue;
    if (c.state == "failed") std::cerr << "campaign " << c.id << " (" << c.name << ") failed: " << c.error << "\n";
    if (c.state != "done") continue;
    std::cerr << "campaign " << c.id << " (" << c.name << ") done; results in " << store->path().string() << ", trial folders in "
              << podium::store::campaign_run_dir(options.database, c).string() << "\n";
  }
  return code;
}

// A running campaign or stage with no scheduler alive is shown "stopped" (`podium run` resumes it).
std::string shown_state(const Json& state, const Json& campaign) {
  return state == "running" && campaign["scheduler"] == "none" ? "stopped" : state.get<std::string>();
}

int cmd_status(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>(), "campaign id or name")("json", "print JSON");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, "status", "[CAMPAIGN] [--json] [--db PATH]", argc, argv)) return 0;
  auto store = open_read(cmd);
  const fs::path db = cmd.vm["db"].as<std::string>();
  std::vector<podium::store::CampaignRecord> list;
  if (cmd.vm.count("campaign")) list.push_back(*store->campaign(campaign_id(*store, cmd.vm["campaign"].as<std::string>())));
  else list = store->campaigns();
  Json out = Json::array();
  const bool alive = podium::store::WriterLock::held(db);
  for (const auto& c : list) out.push_back(status_json(*store, c, db, alive));
  if (cmd.vm.count("json")) {
    std::cout << (cmd.vm.count("campaign") ? out[0] : out).dump(2) << "\n";
    return 0;
  }
  std::printf("%-5s %-24s %-10s %9s %7s %7s %7s  %s\n", "id", "name", "state", "done", "failed", "running", "pending", "created");
  for (const auto& c : out) {
    const std::string done = std::to_string(c["done"].get<long>()) + "/" + std::to_string(c["budget_trials"].get<long>());
    std::printf("%-5lld %-24s %-10s %9s %7ld %7ld %7ld  %s\n", c["id"].get<long long>(), c["name"].get<std::string>().c_str(),
                shown_state(c["state"], c).c_str(), done.c_str(), c["failed"].get<long>(), c["running"].get<long>(),
                c["pending"].get<long>(), fmt_time(c["created_at"].get<double>()).c_str());
    if (!c["error"].get<std::string>().empty()) std::printf("  error: %s\n", c["error"].get<std::string>().c_str());
    if (!cmd.vm.count("campaign")) continue;
    std::printf("  run folder: %s\n", c["run_dir"].get<std::string>().c_str());
    for (const auto& s : c["stages"]) {
      std::printf("  stage %d %-16s %-10s task=%s search=%s %ld/%ld done, %ld failed, %ld running, %.1f s\n",
                  s["index"].get<int>(), s["name"].get<std::string>().c_str(), shown_state(s["state"], c).c_str(),
                  s["task"].get<std::string>().c_str(), s["algorithm"].get<std::string>().c_str(), s["done"].get<long>(),
                  s["budget_trials"].get<long>(), s["failed"].get<long>(), s["running"].get<long>(),
                  s["elapsed_s"].get<double>());
      std::string names;
      for (const auto& o : s["objectives"]) names += (names.empty() ? "    objectives: " : ", ") + named_column(o);
      for (std::size_t i = 0; i < s["features"].size(); ++i)
        names += (i == 0 ? (names.empty() ? "    features: " : "; features: ") : ", ") + named_column(s["features"][i]);
      if (!names.empty()) std::printf("%s\n", names.c_str());
      for (const auto& a : s["running_attempts"]) {
        const std::string where = a["job_id"].get<std::string>().empty() ? a["worker"].get<std::string>()
                                                                         : "slurm job " + a["job_id"].get<std::string>();
        std::printf("    trial %s attempt %d on %s (%s)%s\n", a["name"].get<std::string>().c_str(), a["attempt"].get<int>(),
                    a["host"].get<std::string>().empty() ? "?" : a["host"].get<std::string>().c_str(), where.c_str(),
                    a["interrupted"].get<bool>() ? ": interrupted, its scheduler is gone" : "");
      }
    }
  }
  return 0;
}

// `value` to `digits` significant digits.
std::string significant(double value, int digits) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

// Rows padded to their widest cell, names and states left, numbers right; the last cell as it is.
void print_padded(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(rows[0].size() - 1, 0);
  for (const auto& row : rows)
    for (std::size_t i = 0; i < width.size(); ++i) width[i] = std::max(width[i], row[i].size());
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t i = 0; i < width.size(); ++i) {
      const std::string pad(width[i] - row[i].size(), ' ');
      line += i < 2 ? row[i] + pad + "  " : pad + row[i] + "  ";
    }
    line += row.back();
    while (!line.empty() && line.back() == ' ') line.pop_back();
    std::printf("%s\n", line.c_str());
  }
}

int cmd_trials(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name")("json", "print JSON");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, "trials", "CAMPAIGN [--json] [--db PATH]", argc, argv)) return 0;
  auto store = open_read(cmd);
  const auto id = campaign_id(*store, cmd.vm["campaign"].as<std::string>());
  if (cmd.vm.count("json")) {
    std::cout << podium::orchestrator::export_campaign(*store, id, "json");
    return 0;
  }
  // Per stage, one row per trial under the task's objective and feature names; columns padded to
  // their widest cell; the last one (the error) is not.
  bool first = true;
  for (const auto& st : store->stages(id)) {
    const Json objectives = podium::store::objective_entries(st.description);
    const Json features = podium::store::feature_entries(st.description);
    std::vector<std::string> header = {"trial", "state", "attempts"};
    for (const auto& o : objectives) header.push_back(named_column(o));
    header.insert(header.end(), {"strategy", "id"});
    for (const auto& f : features) header.push_back(named_column(f));
    header.push_back("error");
    std::vector<std::vector<std::string>> rows = {header};
    const auto labels = store->strategy_labels(st.id);
    for (const auto& t : store->trials(st.id)) {
      std::vector<std::string> row = {podium::store::trial_name(st.name, t.index), t.state, std::to_string(t.attempts)};
      for (std::size_t i = 0; i < objectives.size(); ++i) {
        const bool has = t.objectives.is_array() && i < t.objectives.size() && t.objectives[i].is_number();
        row.push_back(has ? significant(t.objectives[i].get<double>(), 4) : "-");
      }
      const auto label = t.strategy ? labels.find(*t.strategy) : labels.end();
      row.insert(row.end(), {label != labels.end() ? std::to_string(label->second) : "-", std::to_string(t.id)});
      for (std::size_t i = 0; i < features.size(); ++i)
        row.push_back(i < t.features.size() ? significant(t.features[i], 3) : "-");
      row.push_back(error_line(t.error));
      rows.push_back(std::move(row));
    }
    if (!first) std::printf("\n");
    first = false;
    print_padded(rows);
  }
  return 0;
}

// The trial `name` ("<stage>/<index>", as `podium trials` shows it) of campaign `c`: its stage and index.
std::pair<podium::store::StageRecord, std::int64_t> find_trial(const Store& store, const podium::store::CampaignRecord& c,
                                                               const std::string& name) {
  const auto slash = name.rfind('/');
  const std::string index = slash == std::string::npos ? "" : name.substr(slash + 1);
  const bool digits = !index.empty() && index.size() < 10 &&
                      std::all_of(index.begin(), index.end(), [](unsigned char ch) { return std::isdigit(ch) != 0; });
  if (digits) {
    const std::string stage = name.substr(0, slash);
    const std::int64_t wanted = std::stoll(index);
    for (const auto& st : store.stages(c.id))
      if (st.name == stage)
        for (const auto& t : store.trials(st.id))
          if (t.index == wanted) return {st, t.index};
  }
  throw podium::base::UserError("campaign " + std::to_string(c.id) + " (" + c.name + ") has no trial \"" + name +
                                "\" (trial names are <stage>/<index>, as podium trials " + std::to_string(c.id) + " shows them)");
}

// What a trial's attempts wrote to stderr (its trial.log), whole or its last N lines; --path
// prints the file's path instead (e.g. for tail -f).
int cmd_log(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name")(
      "trial", po::value<std::string>()->required(), "trial name <stage>/<index>, e.g. weaker/0")(
      "tail", po::value<int>(), "only the last N lines")("path", "print the log file's path");
  cmd.positional.add("campaign", 1).add("trial", 1);
  if (!parse(cmd, "log", "CAMPAIGN TRIAL [--tail N] [--path] [--db PATH]", argc, argv)) return 0;
  const fs::path db = cmd.vm["db"].as<std::string>();
  auto store = open_read(cmd);
  const auto c = store->campaign(campaign_id(*store, cmd.vm["campaign"].as<std::string>()));
  const auto [stage, index] = find_trial(*store, *c, cmd.vm["trial"].as<std::string>());
  const fs::path log =
      podium::store::trial_folder(podium::store::campaign_run_dir(db, *c), stage, index) / podium::store::kTrialLog;
  if (cmd.vm.count("path")) {
    std::cout << log.string() << "\n";
    return 0;
  }
  if (cmd.vm.count("tail") && cmd.vm["tail"].as<int>() < 0)
    throw podium::base::UserError("--tail: " + std::to_string(cmd.vm["tail"].as<int>()) + " is negative");
  std::ifstream in(log, std::ios::binary);
  if (!in) throw std::runtime_error(log.string() + ": no log (the trial has not started, or its folder was removed)");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(std::move(line));
  const std::size_t from =
      cmd.vm.count("tail") ? lines.size() - std::min<std::size_t>(lines.size(), cmd.vm["tail"].as<int>()) : 0;
  for (std::size_t i = from; i < lines.size(); ++i) std::cout << lines[i] << "\n";
  return 0;
}

int cmd_control(const std::string& action, int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, action, "CAMPAIGN [--db PATH]", argc, argv)) return 0;
  const std::string db = cmd.vm["db"].as<std::string>();
  if (!fs::exists(db)) throw podium::base::UserError(db + ": no such database (podium submit creates it)");
  auto store = Store::open(db, Store::Access::read_write);
  const std::string& name = cmd.vm["campaign"].as<std::string>();
  podium::orchestrator::control_campaign(*store, name, action);
  const auto c = store->find_campaign(name);
  const std::map<std::string, std::string> what = {{"pause", "paused: no new trials start, running ones finish"},
                                                   {"resume", "queued again: podium run continues it"},
                                                   {"cancel", "cancelled: running trials are stopped, no new ones start"}};
  std::cout << "campaign " << c->id << " (" << c->name << ") " << what.at(action) << "\n";
  return 0;
}

int cmd_extend(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name")(
      "stage", po::value<std::string>(), "the stage to extend (default and only choice: the last)")(
      "add-trials", po::value<std::int64_t>()->required(), "trials to add to the stage's budget");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, "extend", "CAMPAIGN [--stage NAME] --add-trials N [--db PATH]", argc, argv)) return 0;
  const std::string db = cmd.vm["db"].as<std::string>();
  if (!fs::exists(db)) throw podium::base::UserError(db + ": no such database (podium submit creates it)");
  auto store = Store::open(db, Store::Access::read_write);
  const auto e = podium::orchestrator::extend_campaign(*store, cmd.vm["campaign"].as<std::string>(),
                                                       cmd.vm.count("stage") ? cmd.vm["stage"].as<std::string>() : "",
                                                       cmd.vm["add-trials"].as<std::int64_t>());
  std::cout << "campaign " << e.campaign_id << " (" << e.campaign_name << ") stage \"" << e.stage << "\": budget raised from "
            << e.budget_before << " to " << e.budget_after
            << " trials; queued again: podium run continues its search where it stopped\n";
  return 0;
}

int cmd_export(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name")(
      "format", po::value<std::string>()->default_value("csv"), "csv or json")("metrics",
                                                                               "with each trial's metric series (JSON only)");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, "export", "CAMPAIGN --format csv|json [--metrics] [--db PATH]", argc, argv)) return 0;
  auto store = open_read(cmd);
  std::cout << podium::orchestrator::export_campaign(*store, campaign_id(*store, cmd.vm["campaign"].as<std::string>()),
                                                     cmd.vm["format"].as<std::string>(), cmd.vm.count("metrics") > 0);
  return 0;
}

int cmd_summary(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::vector<std::string>>()->required(), "campaign ids or names")(
      "json", "print JSON")("short", "per stage only its trials, best trial, strategy count and the task's tables");
  cmd.positional.add("campaign", -1);
  if (!parse(cmd, "summary", "CAMPAIGN... [--json] [--short] [--db PATH]", argc, argv)) return 0;
  auto store = open_read(cmd);
  std::vector<std::int64_t> ids;
  for (const auto& c : cmd.vm["campaign"].as<std::vector<std::string>>()) ids.push_back(campaign_id(*store, c));
  const bool json = cmd.vm.count("json") > 0;
  if (ids.size() == 1) {
    const Json summary = podium::store::campaign_summary(*store, ids[0]);
    std::cout << (json ? summary.dump(2) + "\n" : podium::store::format_summary(summary, cmd.vm.count("short") > 0));
  } else {
    const Json comparison = podium::store::compare_campaigns(*store, ids);
    std::cout << (json ? comparison.dump(2) + "\n" : podium::store::format_comparison(comparison));
  }
  return 0;
}

int cmd_tasks(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("task", po::value<std::string>(), "task name (default: every installed task)")("json", "print JSON")(
      "all", "also the test plugins the build makes for podium's own tests")(
      "config", po::value<std::string>(), "describe NAME at this config (JSON object, e.g. '{\"stage\": \"novel\"}')");
  cmd.positional.add("task", 1);
  if (!parse(cmd, "tasks", "[NAME] [--json] [--all] [--config JSON]", argc, argv)) return 0;
  Json config = Json::object();
  if (cmd.vm.count("config")) {
    const std::string text = cmd.vm["config"].as<std::string>();
    config = Json::parse(text, nullptr, false);
    if (config.is_discarded() || !config.is_object())
      throw podium::base::UserError("--config: " + text + " is not a JSON object");
  }
  const Json tasks = podium::orchestrator::list_tasks(
      worker_binary(), cmd.vm.count("task") ? cmd.vm["task"].as<std::string>() : "", cmd.vm.count("all") > 0, config);
  if (cmd.vm.count("json")) std::cout << (cmd.vm.count("task") ? tasks[0] : tasks).dump(2) << "\n";
  else std::cout << podium::orchestrator::format_tasks(tasks);
  return 0;
}

int cmd_serve(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("port", po::value<int>()->default_value(8080), "TCP port (0: any free port)")(
      "host", po::value<std::string>()->default_value("127.0.0.1"), "address to listen on")(
      "static", po::value<std::string>(), "front-end folder (default: <bin>/../share/podium/web)");
  if (!parse(cmd, "serve", "[--port N] [--host 127.0.0.1] [--db PATH]", argc, argv)) return 0;
  podium::web_dashboard::ServeOptions options;
  options.database = cmd.vm["db"].as<std::string>();
  options.host = cmd.vm["host"].as<std::string>();
  options.port = cmd.vm["port"].as<int>();
  if (options.port < 0 || options.port > 65535)
    throw podium::base::UserError("--port: " + std::to_string(options.port) + " is not in [0, 65535]");
  options.static_dir = cmd.vm.count("static") ? fs::path(cmd.vm["static"].as<std::string>())
                                              : podium::web_dashboard::default_static_dir(worker_binary());
  return podium::web_dashboard::serve(options, std::cout);
}

int dispatch(const std::string& command, int argc, char** argv) {
  if (command == "submit") return cmd_submit(argc, argv);
  if (command == "run") return cmd_run(argc, argv);
  if (command == "status") return cmd_status(argc, argv);
  if (command == "trials") return cmd_trials(argc, argv);
  if (command == "log") return cmd_log(argc, argv);
  if (command == "pause" || command == "resume" || command == "cancel") return cmd_control(command, argc, argv);
  if (command == "extend") return cmd_extend(argc, argv);
  if (command == "export") return cmd_export(argc, argv);
  if (command == "summary") return cmd_summary(argc, argv);
  if (command == "serve") return cmd_serve(argc, argv);
  if (command == "tasks") return cmd_tasks(argc, argv);
  if (command == "tool") return podium::orchestrator::run_task_tool({argv + 1, argv + argc}, std::cout, std::cerr);
  if (command == "worker") return podium::orchestrator::run_worker();
  if (command == "trial" && argc == 3 && std::string(argv[1]) == "--batch")
    return podium::orchestrator::run_batch_trial(argv[2]);  // inside a Slurm job
  if (command == "version" || command == "--version") {
    std::cout << "podium " << podium::base::version() << " (" << podium::base::compiler_id() << ", " << podium::base::build_type()
              << ")\n"
              << podium::orchestrator::blas_kernels_line() << "\n";
    return 0;
  }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  std::cerr << "podium: unknown command \"" << command << "\"\n" << kUsage;
  return 2;
}

// An error as one bounded line: control characters (a newline in a JSON key, a terminal escape)
// escaped, and anything past 1000 bytes cut at a character boundary.
std::string error_line(const std::string& what) {
  constexpr std::size_t kMax = 1000;
  std::string out;
  for (const char ch : what) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7F) {
      out += ch;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", c);
      out += escaped;
    }
  }
  if (out.size() <= kMax) return out;
  std::size_t cut = kMax;
  while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 sequence
  return out.substr(0, cut) + "... (" + std::to_string(out.size()) + " bytes in all)";
}

}  // namespace

int main(int argc, char** argv) {
  podium::orchestrator::use_native_blas_kernels(argv);
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  try {
    return dispatch(command, argc - 1, argv + 1);
  } catch (const po::error& e) {
    std::cerr << "podium " << command << ": " << error_line(e.what()) << " (see podium " << command << " --help)\n";
    return 2;
  } catch (const podium::base::UserError& e) {
    std::cerr << "podium: " << error_line(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "podium: " << error_line(e.what()) << "\n";
    return 1;
  }
}
