// The `podium` command line: submit, run, status, trials, pause, resume, cancel, export (and the
// internal `worker`). Exit codes: 0 ok, 1 runtime failure, 2 usage or spec error.
#include <unistd.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/version.h"
#include "podium/orchestrator/campaigns.h"
#include "podium/orchestrator/scheduler.h"
#include "podium/store/store.h"
#include "podium/web_dashboard/server.h"
#include "trial_runner.h"
#include "worker.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using podium::base::Json;
using podium::store::Store;

namespace {

constexpr const char* kUsage = R"(usage: podium <command> [options]

commands:
  submit SPEC.json           validate a campaign spec and queue it (prints the campaign id)
  run [--workers N] [--follow] [--log-json]
                             run queued and resumable campaigns until none is left
  status [CAMPAIGN] [--json] campaigns and their progress
  trials CAMPAIGN [--json]   the trials of a campaign
  pause|resume|cancel CAMPAIGN
  export CAMPAIGN --format csv|json
  serve [--port N] [--host H] the read-only web dashboard (default http://127.0.0.1:8080/)
  version

every command takes --db PATH (default ./podium.db) and --help.
)";

struct Command {
  po::options_description options;
  po::positional_options_description positional;
  po::variables_map vm;
};

// Parses a subcommand's options; returns false (after printing help) when --help was given.
bool parse(Command& cmd, const std::string& name, const std::string& synopsis, int argc, char** argv) {
  cmd.options.add_options()("db", po::value<std::string>()->default_value("podium.db"), "database file")(
      "help,h", "show this help");
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
  const auto c = store.find_campaign(id_or_name);
  if (!c) throw podium::base::UserError("no campaign \"" + id_or_name + "\" in " + store.path().string());
  return c->id;
}

std::string fmt_time(double unix_s) {
  if (unix_s <= 0) return "-";
  const std::time_t t = static_cast<std::time_t>(unix_s);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  return buffer;
}

Json status_json(const Store& store, const podium::store::CampaignRecord& c, const fs::path& db) {
  const auto counts = store.trial_counts(c.id);
  Json stages = Json::array();
  std::int64_t budget = 0;
  for (const auto& st : store.stages(c.id)) {
    const auto sc = store.stage_trial_counts(st.id);
    budget += st.budget_trials;
    std::map<std::int64_t, std::int64_t> index_of;
    for (const auto& t : store.trials(st.id)) index_of[t.id] = t.index;
    Json running = Json::array();
    for (const auto& a : store.running_attempts(st.id))
      running.push_back({{"trial", index_of[a.trial_id]}, {"attempt", a.number}, {"worker", a.worker},
                         {"host", a.host}, {"job_id", a.job_id}, {"started_at", a.started_at}});
    stages.push_back({{"index", st.index},     {"name", st.name},     {"task", st.task},
                      {"algorithm", st.algorithm}, {"state", st.state}, {"budget_trials", st.budget_trials},
                      {"done", sc.done},       {"failed", sc.failed}, {"running", sc.running},
                      {"pending", sc.pending + sc.interrupted}, {"cancelled", sc.cancelled},
                      {"elapsed_s", st.elapsed_s}, {"running_attempts", running}});
  }
  return {{"id", c.id},
          {"name", c.name},
          {"state", c.state},
          {"seed", c.seed},
          {"budget_trials", budget},
          {"done", counts.done},
          {"failed", counts.failed},
          {"running", counts.running},
          {"pending", counts.pending + counts.interrupted},
          {"cancelled", counts.cancelled},
          {"created_at", c.created_at},
          {"started_at", c.started_at},
          {"finished_at", c.finished_at},
          {"run_dir", podium::orchestrator::campaign_run_dir(db, c).string()},
          {"error", c.error},
          {"stages", stages}};
}

int cmd_submit(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("spec", po::value<std::string>()->required(), "campaign spec (JSON)");
  cmd.positional.add("spec", 1);
  if (!parse(cmd, "submit", "SPEC.json [--db PATH]", argc, argv)) return 0;
  const std::string file = cmd.vm["spec"].as<std::string>();
  const Json spec = podium::base::read_json_file(file);
  auto store = Store::open(cmd.vm["db"].as<std::string>(), Store::Access::read_write);
  const auto id = podium::orchestrator::submit_campaign(*store, spec, file, worker_binary());
  std::cout << id << "\n";
  return 0;
}

int cmd_run(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("workers", po::value<int>()->default_value(2), "worker processes")(
      "follow", "keep waiting for new campaigns")("log-json", "machine-readable events on stdout instead of progress");
  if (!parse(cmd, "run", "[--workers N] [--follow] [--log-json] [--db PATH]", argc, argv)) return 0;
  const int workers = cmd.vm["workers"].as<int>();
  if (workers < 1) throw podium::base::UserError("--workers: " + std::to_string(workers) + " is not >= 1");
  podium::orchestrator::SchedulerOptions options;
  options.workers = static_cast<std::size_t>(workers);
  options.follow = cmd.vm.count("follow") > 0;
  options.log_json = cmd.vm.count("log-json") > 0;
  options.progress = !options.log_json && ::isatty(STDERR_FILENO);
  options.worker_binary = worker_binary();
  options.database = cmd.vm["db"].as<std::string>();
  auto store = Store::open(options.database, Store::Access::read_write);
  podium::orchestrator::run_scheduler(*store, options);
  if (!options.log_json) {
    for (const auto& c : store->campaigns()) {
      if (c.state != "done" || c.finished_at < podium::store::now_unix_s() - 5) continue;
      std::cerr << "campaign " << c.id << " (" << c.name << ") done; results in " << store->path().string()
                << ", trial folders in " << podium::orchestrator::campaign_run_dir(options.database, c).string() << "\n";
    }
  }
  return 0;
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
  for (const auto& c : list) out.push_back(status_json(*store, c, db));
  if (cmd.vm.count("json")) {
    std::cout << (cmd.vm.count("campaign") ? out[0] : out).dump(2) << "\n";
    return 0;
  }
  std::printf("%-5s %-24s %-10s %9s %7s %7s %7s  %s\n", "id", "name", "state", "done", "failed", "running", "pending", "created");
  for (const auto& c : out) {
    const std::string done = std::to_string(c["done"].get<long>()) + "/" + std::to_string(c["budget_trials"].get<long>());
    std::printf("%-5lld %-24s %-10s %9s %7ld %7ld %7ld  %s\n", c["id"].get<long long>(), c["name"].get<std::string>().c_str(),
                c["state"].get<std::string>().c_str(), done.c_str(), c["failed"].get<long>(), c["running"].get<long>(),
                c["pending"].get<long>(), fmt_time(c["created_at"].get<double>()).c_str());
    if (!cmd.vm.count("campaign")) continue;
    std::printf("  run folder: %s\n", c["run_dir"].get<std::string>().c_str());
    for (const auto& s : c["stages"]) {
      std::printf("  stage %d %-16s %-10s task=%s search=%s %ld/%ld done, %ld failed, %ld running, %.1f s\n",
                  s["index"].get<int>(), s["name"].get<std::string>().c_str(), s["state"].get<std::string>().c_str(),
                  s["task"].get<std::string>().c_str(), s["algorithm"].get<std::string>().c_str(), s["done"].get<long>(),
                  s["budget_trials"].get<long>(), s["failed"].get<long>(), s["running"].get<long>(), s["elapsed_s"].get<double>());
      for (const auto& a : s["running_attempts"]) {
        const std::string where = a["job_id"].get<std::string>().empty() ? a["worker"].get<std::string>()
                                                                         : "slurm job " + a["job_id"].get<std::string>();
        std::printf("    trial %lld attempt %d on %s (%s)\n", a["trial"].get<long long>(), a["attempt"].get<int>(),
                    a["host"].get<std::string>().empty() ? "?" : a["host"].get<std::string>().c_str(), where.c_str());
      }
    }
  }
  return 0;
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
  std::printf("%-12s %6s %-11s %8s %14s  %s\n", "stage", "trial", "state", "attempts", "objective", "features / error");
  for (const auto& st : store->stages(id)) {
    for (const auto& t : store->trials(st.id)) {
      std::ostringstream features;
      for (double f : t.features) features << f << " ";
      const std::string objective = t.objectives.is_array() && !t.objectives.empty() ? t.objectives[0].dump() : "-";
      std::printf("%-12s %6lld %-11s %8d %14s  %s\n", st.name.c_str(), static_cast<long long>(t.index), t.state.c_str(),
                  t.attempts, objective.c_str(), t.error.empty() ? features.str().c_str() : t.error.c_str());
    }
  }
  return 0;
}

int cmd_control(const std::string& action, int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, action, "CAMPAIGN [--db PATH]", argc, argv)) return 0;
  auto store = Store::open(cmd.vm["db"].as<std::string>(), Store::Access::read_write);
  podium::orchestrator::control_campaign(*store, cmd.vm["campaign"].as<std::string>(), action);
  return 0;
}

int cmd_export(int argc, char** argv) {
  Command cmd;
  cmd.options.add_options()("campaign", po::value<std::string>()->required(), "campaign id or name")(
      "format", po::value<std::string>()->default_value("csv"), "csv or json");
  cmd.positional.add("campaign", 1);
  if (!parse(cmd, "export", "CAMPAIGN --format csv|json [--db PATH]", argc, argv)) return 0;
  auto store = open_read(cmd);
  std::cout << podium::orchestrator::export_campaign(*store, campaign_id(*store, cmd.vm["campaign"].as<std::string>()),
                                                     cmd.vm["format"].as<std::string>());
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
  if (command == "pause" || command == "resume" || command == "cancel") return cmd_control(command, argc, argv);
  if (command == "export") return cmd_export(argc, argv);
  if (command == "serve") return cmd_serve(argc, argv);
  if (command == "worker") return podium::orchestrator::run_worker();
  if (command == "trial" && argc == 3 && std::string(argv[1]) == "--batch")
    return podium::orchestrator::run_batch_trial(argv[2]);  // inside a Slurm job
  if (command == "version") {
    std::cout << "podium " << podium::base::version() << " (" << podium::base::compiler_id() << ", "
              << podium::base::build_type() << ")\n";
    return 0;
  }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  std::cerr << "podium: unknown command \"" << command << "\"\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  try {
    return dispatch(command, argc - 1, argv + 1);
  } catch (const po::error& e) {
    std::cerr << "podium " << command << ": " << e.what() << " (see podium " << command << " --help)\n";
    return 2;
  } catch (const podium::base::UserError& e) {
    std::cerr << "podium: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "podium: " << e.what() << "\n";
    return 1;
  }
}
