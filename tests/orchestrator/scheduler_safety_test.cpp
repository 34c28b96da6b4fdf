// The hardening of `podium run` and its readers, each with real `podium` processes and a
// real SQLite database: one scheduler per database file whatever path reaches it,
// names that never reach the filesystem as they are, a relative run_dir fixed at submit,
// readers on a read-only filesystem, SIGTERM/SIGINT with a hung worker, and states
// that tell the truth after pause, cancel and kill -9.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>

#include "campaign_spec.h"
#include "podium/base/json.h"
#include "podium/store/store.h"
#include "process.h"

namespace podium::orchestrator {
namespace {

namespace fs = std::filesystem;
using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using store::Store;

Json landscape(const std::string& stage_name, int trials, const Json& config, int retries = 0) {
  return {{"name", "safety"},
          {"seed", 3},
          {"workers", 2},
          {"retries", retries},
          {"trial_timeout_s", 600},
          {"stages", Json::array({{{"name", stage_name},
                                   {"task", "landscape"},
                                   {"preset", "smoke"},
                                   {"config", config},
                                   {"search", {{"algorithm", "random"}}},
                                   {"budget", {{"trials", trials}}}}})}};
}

// Trials 0 and 1 hang on their first attempt (the landscape task's failure injection).
const Json kFirstAttemptsHang = {{"failures", Json::array({{{"mode", "hang"}, {"trials", {0, 1}}, {"attempts", 1}}})}};

// Polls the store until `running` attempts run, or `pid` has exited (then false).
bool wait_for_running(const fs::path& db, std::int64_t id, std::int64_t running, pid_t pid) {
  return podium::testing::wait_until(
      pid, [&] { return fs::exists(db) && Store::open(db, Store::Access::read_only)->trial_counts(id).running >= running; });
}

TEST(SingleWriter, ASecondSchedulerThroughASymlinkOrAHardLinkIsRefused) {
  TempDir dir;
  fs::create_directories(dir / "data");
  podium::testing::write_file(dir / "spec.json", landscape("explore", 6, {{"sleep_s", 0.3}}).dump());
  ASSERT_EQ(run_podium({"submit", "spec.json", "--db", "data/podium.db"}, dir.path()).exit_code, 0);
  const pid_t first = podium::testing::spawn_podium({"run", "--db", "data/podium.db"}, dir.path());
  ASSERT_TRUE(wait_for_running(dir / "data/podium.db", 1, 1, first));

  fs::create_symlink(dir / "data/podium.db", dir / "symlink.db");
  const auto through_symlink = run_podium({"run", "--db", "symlink.db"}, dir.path());
  EXPECT_EQ(through_symlink.exit_code, 1);
  EXPECT_NE(through_symlink.err.find("another `podium run` is using this database"), std::string::npos) << through_symlink.err;
  const auto status = Json::parse(run_podium({"status", "1", "--json", "--db", "symlink.db"}, dir.path()).out);
  EXPECT_EQ(status["scheduler"], "alive");

  fs::create_hard_link(dir / "data/podium.db", dir / "hardlink.db");
  const auto through_hard_link = run_podium({"run", "--db", "hardlink.db"}, dir.path());
  EXPECT_EQ(through_hard_link.exit_code, 1);
  EXPECT_NE(through_hard_link.err.find("another `podium run` is using this database"), std::string::npos)
      << through_hard_link.err;
  EXPECT_FALSE(fs::exists(dir / "hardlink.db-wal")) << "the refused scheduler opened the database";
  fs::remove(dir / "hardlink.db");

  EXPECT_EQ(podium::testing::wait_process(first), 0);
  auto s = Store::open(dir / "data/podium.db", Store::Access::read_only);
  EXPECT_EQ(s->campaign(1)->state, "done");
  for (const auto& t : s->campaign_trials(1)) {
    EXPECT_EQ(t.state, "done") << "trial " << t.index;
    EXPECT_EQ(s->attempts(t.id).size(), 1u) << "trial " << t.index << " ran more than once";
  }
}

TEST(SingleWriter, AHardLinkedDatabaseIsNotOpenedForWriting) {
  TempDir dir;
  podium::testing::submit_spec(dir.path(), landscape("explore", 2, Json::object()));
  fs::create_hard_link(dir / "podium.db", dir / "other.db");
  const auto r = run_podium({"run"}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("has 2 hard links"), std::string::npos) << r.err;
}

TEST(RunFolders, AStageNameCannotLeadOutOfTheRunFolder) {
  TempDir dir;
  const fs::path base = dir / "a/b/c";  // "x/../../../.." climbs from the stage folder to a/b
  fs::create_directories(base);
  const auto id = podium::testing::submit_spec(base, landscape("x/../../../../ESCAPED", 3, {{"artifact", true}}));
  ASSERT_EQ(run_podium({"run"}, base).exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / "a/b/ESCAPED"));
  const auto status = Json::parse(run_podium({"status", id, "--json"}, base).out);
  const std::string run_dir = status["run_dir"];
  auto s = Store::open(base / "podium.db", Store::Access::read_only);
  const auto trials = s->campaign_trials(std::stoll(id));
  ASSERT_EQ(trials.size(), 3u);
  for (const auto& t : trials) {
    ASSERT_EQ(t.state, "done");
    for (const auto& a : s->artifacts(t.id)) {
      const std::string path = fs::weakly_canonical(a.path).string();
      EXPECT_EQ(path.rfind(run_dir + "/stage-0-x_.._.._.._.._ESCAPED/trial-", 0), 0u) << path;
    }
  }
}

TEST(RunFolders, ARelativeRunDirIsRelativeToTheSpecFileAndStoredAbsolute) {
  TempDir dir;
  fs::create_directories(dir / "specs");
  fs::create_directories(dir / "elsewhere");
  Json spec = landscape("explore", 2, {{"artifact", true}});
  spec["run_dir"] = "out";
  podium::testing::write_file(dir / "specs/spec.json", spec.dump());
  ASSERT_EQ(run_podium({"submit", "specs/spec.json"}, dir.path()).exit_code, 0);
  const std::string db = (dir / "podium.db").string();
  ASSERT_EQ(run_podium({"run", "--db", db}, dir / "elsewhere").exit_code, 0);

  const fs::path expected = dir / "specs/out";
  auto s = Store::open(db, Store::Access::read_only);
  EXPECT_EQ(s->campaign(1)->run_dir, expected.string());
  EXPECT_TRUE(fs::exists(expected / "stage-0-explore/trial-0"));
  EXPECT_FALSE(fs::exists(dir / "elsewhere/out"));
  const auto status = Json::parse(run_podium({"status", "1", "--json", "--db", db}, dir / "specs").out);
  EXPECT_EQ(status["run_dir"], expected.string());
}

// Runs the shell `script` in a new user and mount namespace where `source` is bind-mounted
// read-only on `target` (no root needed where unprivileged user namespaces are allowed). Returns
// the shell's exit code, or -1 if such a namespace cannot be made here.
int with_read_only_mount(const fs::path& source, const fs::path& target, const std::string& script) {
  if (std::system("unshare -rm true > /dev/null 2>&1") != 0) return -1;
  const fs::path file = target.parent_path() / "script.sh";
  const std::string mount = "mount --bind -o ro '" + source.string() + "' '" + target.string() + "' || exit 3\n";
  podium::testing::write_file(file, mount + script);
  const int status = std::system(("unshare -rm sh " + file.string()).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A results archive on a read-only filesystem: SQLite cannot create the WAL's -shm file there.
// Without unshare, reproduce by hand: `mount --bind -o ro DIR MNT; podium status --db MNT/podium.db`.
TEST(ReadOnlyFilesystem, StatusTrialsExportAndServeReadADatabaseThere) {
  TempDir dir;
  fs::create_directories(dir / "archive");
  fs::create_directories(dir / "mnt");
  const auto id = podium::testing::submit_spec(dir / "archive", landscape("explore", 3, Json::object()));
  ASSERT_EQ(run_podium({"run"}, dir / "archive").exit_code, 0);
  ASSERT_FALSE(fs::exists(dir / "archive/podium.db-shm"));  // a cleanly closed WAL database

  const std::string podium = podium::testing::podium_binary().string();
  const std::string db = (dir / "mnt/podium.db").string(), out = (dir / "out").string();
  std::string script;
  for (const std::string& c : {std::string("status"), "trials " + id, "export " + id + " --format csv"})
    script +=
        podium + " " + c + " --db " + db + " >> " + out + " 2>&1 && echo ok-" + c.substr(0, c.find(' ')) + " >> " + out + "\n";
  // serve: the dashboard answers from the read-only database, then is stopped.
  script += podium + " serve --port 0 --db " + db + " > " + out + ".url 2>&1 &\nSERVER=$!\n" +
            "for i in $(seq 400); do grep -q http " + out + ".url && break; sleep 0.05; done\n" +
            "curl -sf \"$(grep -o 'http://[^ ]*' " + out + ".url | head -1)api/campaigns\" >> " + out + " && echo ok-serve >> " +
            out + "\nkill $SERVER\nwait $SERVER\nexit 0\n";
  const int rc = with_read_only_mount(dir / "archive", dir / "mnt", script);
  if (rc < 0) GTEST_SKIP() << "unshare -rm (a user and mount namespace) is not available here";
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* ok : {"ok-status", "ok-trials", "ok-export", "ok-serve"})
    EXPECT_NE(text.find(ok), std::string::npos) << ok << " missing; output:\n" << text;
  EXPECT_EQ(text.find("unable to open database file"), std::string::npos) << text;
}

// SIGTERM and SIGINT stop the scheduler at once while its workers hang: the hung workers are
// killed, their attempts recorded interrupted, the exit code says work was abandoned, and the
// next `podium run` runs them again.
TEST(Signals, StoppingWhileAWorkerHangsExitsNonZeroAndTheAttemptsRunAgain) {
  for (const int signal : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(strsignal(signal));
    TempDir dir;
    const auto id = std::stoll(podium::testing::submit_spec(dir.path(), landscape("explore", 4, kFirstAttemptsHang)));
    const pid_t scheduler = podium::testing::spawn_podium({"run"}, dir.path());
    ASSERT_TRUE(wait_for_running(dir / "podium.db", id, 2, scheduler));
    ::kill(scheduler, signal);
    EXPECT_EQ(podium::testing::wait_process(scheduler), 128 + signal);
    {
      auto s = Store::open(dir / "podium.db", Store::Access::read_only);
      for (const auto& t : s->campaign_trials(id)) {
        if (t.index > 1) continue;
        EXPECT_EQ(t.state, "interrupted") << "trial " << t.index;
        EXPECT_EQ(s->attempts(t.id).at(0).state, "interrupted") << "trial " << t.index;
      }
    }
    const auto again = run_podium({"run"}, dir.path());
    ASSERT_EQ(again.exit_code, 0) << again.err;
    auto s = Store::open(dir / "podium.db", Store::Access::read_only);
    EXPECT_EQ(s->campaign(id)->state, "done");
    EXPECT_EQ(s->trial_counts(id).done, 4);
  }
}

TEST(States, StatusShowsAKilledSchedulerAsGoneAndStagesOfPausedOrCancelledCampaignsAsSuch) {
  TempDir dir;
  const auto id = podium::testing::submit_spec(dir.path(), landscape("explore", 4, kFirstAttemptsHang));
  const pid_t scheduler = podium::testing::spawn_podium({"run"}, dir.path());
  ASSERT_TRUE(wait_for_running(dir / "podium.db", std::stoll(id), 2, scheduler));
  Json live = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(live["scheduler"], "alive");
  EXPECT_FALSE(live["stages"][0]["running_attempts"][0]["interrupted"].get<bool>());
  ::kill(scheduler, SIGKILL);
  podium::testing::wait_process(scheduler);

  const Json gone = Json::parse(run_podium({"status", id, "--json"}, dir.path()).out);
  EXPECT_EQ(gone["scheduler"], "none");
  ASSERT_EQ(gone["stages"][0]["running_attempts"].size(), 2u);
  for (const auto& a : gone["stages"][0]["running_attempts"]) EXPECT_TRUE(a["interrupted"].get<bool>()) << a;
  const auto table = run_podium({"status", id}, dir.path()).out;
  EXPECT_NE(table.find("stopped"), std::string::npos) << table;
  EXPECT_NE(table.find("interrupted, its scheduler is gone"), std::string::npos) << table;

  ASSERT_EQ(run_podium({"pause", id}, dir.path()).exit_code, 0);
  EXPECT_EQ(Json::parse(run_podium({"status", id, "--json"}, dir.path()).out)["stages"][0]["state"], "paused");
  ASSERT_EQ(run_podium({"cancel", id}, dir.path()).exit_code, 0);
  EXPECT_EQ(Json::parse(run_podium({"status", id, "--json"}, dir.path()).out)["stages"][0]["state"], "cancelled");
}

}  // namespace
}  // namespace podium::orchestrator
