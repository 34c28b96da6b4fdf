// Security of `podium serve`: traversal in static and artifact routes, hostile API parameters,
// no write endpoints, loopback-only default bind; and the command's lifecycle.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <fstream>
#include <thread>

#include "dashboard_support.h"
#include "podium/base/error.h"
#include "podium/store/store.h"

namespace podium::web_dashboard {
namespace {

namespace fs = std::filesystem;
using base::Json;
using podium::testing::TempDir;
using testing::raw_status;
using testing::RunningServer;

// A database written directly through the store: one campaign whose run folder is dir/runs,
// with one trial holding artifacts inside and outside that folder.
struct ArtifactFixture {
  TempDir dir;
  fs::path db = dir / "podium.db";
  std::int64_t trial = 0;

  ArtifactFixture() {
    const fs::path runs = dir / "runs";
    fs::create_directories(runs / "trial-0");
    podium::testing::write_file(runs / "trial-0" / "ok.txt", "inside\n");
    podium::testing::write_file(dir / "secret.txt", "outside\n");
    fs::create_symlink(dir / "secret.txt", runs / "trial-0" / "link.txt");
    fs::create_hard_link(dir / "secret.txt", runs / "trial-0" / "hard.txt");
    auto s = store::Store::open(db, store::Store::Access::read_write);
    store::NewStage stage{"s", "landscape", "random"};
    stage.budget_trials = 1;
    const auto campaign = s->add_campaign("c", Json::object(), 1, runs.string(), {stage});
    trial = s->add_trial(s->stages(campaign)[0].id, 0, Json::object(), Json::object(), Json::object(), 1);
    s->complete_trial(trial, {1.0}, {}, {}, Json::object(),
                      {{"ok", (runs / "trial-0" / "ok.txt").string(), "", 7},
                       {"absolute", (dir / "secret.txt").string(), "", 8},
                       {"dotdot", (runs / "trial-0" / ".." / ".." / "secret.txt").string(), "", 8},
                       {"symlink", (runs / "trial-0" / "link.txt").string(), "", 8},
                       {"system", "/etc/passwd", "", 1},
                       {"prefix", (dir / "runs-evil" / "x").string(), "", 1},
                       {"hardlink", (runs / "trial-0" / "hard.txt").string(), "", 8}});
  }
};

TEST(Security, StaticRoutesRefusePathTraversal) {
  ArtifactFixture f;
  RunningServer server(f.db);
  for (const char* path :
       {"/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/vendor/../../podium.db", "/..%2f..%2f..%2fetc%2fpasswd",
        "/%2e%2e%2f%2e%2e%2fetc/passwd", "//etc/passwd", "/vendor/%2e%2e/index.html", "/index.html%00.js", "/./index.html"})
    EXPECT_EQ(raw_status(server.port(), std::string("GET ") + path + " HTTP/1.1"), 404) << path;
  EXPECT_EQ(raw_status(server.port(), "GET /index.html HTTP/1.1"), 200);
}

TEST(Security, ArtifactsOutsideTheRunFolderAreRefused) {
  ArtifactFixture f;
  RunningServer server(f.db);
  auto client = server.client();
  const std::string base = "/api/trials/" + std::to_string(f.trial) + "/artifacts/";
  const auto ok = client.Get((base + "0").c_str());
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
  EXPECT_EQ(ok->body, "inside\n");
  for (int i = 1; i <= 6; ++i) {
    const auto r = client.Get((base + std::to_string(i)).c_str());
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << "artifact " << i;
    EXPECT_EQ(r->body.find("outside\n"), std::string::npos);
    EXPECT_EQ(r->body.find("root:"), std::string::npos);
  }
  for (const char* hostile : {"../../../../etc/passwd", "..%2f..%2fsecret.txt", "-1", "0x0", "1e3", "99"}) {
    const int status = raw_status(server.port(), "GET " + base + hostile + " HTTP/1.1");
    EXPECT_TRUE(status == 400 || status == 404) << hostile << " -> " << status;
  }
}

// A trial's log is looked up by the store's folder rule, then checked as an artifact is: a
// symlink or hard link standing in for it is refused, and a trial without one is a 404.
TEST(Security, TrialLogsOutsideTheRunFolderAreRefused) {
  ArtifactFixture f;
  RunningServer server(f.db);
  auto client = server.client();
  const std::string url = "/api/trials/" + std::to_string(f.trial) + "/log";
  const fs::path log = f.dir / "runs" / "stage-0-s" / "trial-0" / "trial.log";
  EXPECT_EQ(client.Get(url.c_str())->status, 404);
  fs::create_directories(log.parent_path());
  fs::create_symlink(f.dir / "secret.txt", log);
  EXPECT_EQ(client.Get(url.c_str())->status, 403);
  fs::remove(log);
  fs::create_hard_link(f.dir / "secret.txt", log);
  EXPECT_EQ(client.Get(url.c_str())->status, 403);
  fs::remove(log);
  podium::testing::write_file(log, "podium: attempt 1 started\n");
  const auto ok = client.Get(url.c_str());
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200);
  EXPECT_EQ(ok->body, "podium: attempt 1 started\n");
}

// A Range past the end of a streamed artifact is 416, as for the in-memory static files
// (it was 206 with Content-Length 18446743973709551733).
TEST(Security, UnsatisfiableRangesAre416OnArtifactsAndStaticFiles) {
  ArtifactFixture f;
  RunningServer server(f.db);
  const std::string artifact = "GET /api/trials/" + std::to_string(f.trial) + "/artifacts/0 HTTP/1.1";
  EXPECT_EQ(raw_status(server.port(), artifact + "\r\nRange: bytes=99999999999-"), 416);
  EXPECT_EQ(raw_status(server.port(), artifact + "\r\nRange: bytes=7-"), 416);  // ok.txt has 7 bytes
  EXPECT_EQ(raw_status(server.port(), artifact + "\r\nRange: bytes=2-3"), 206);
  EXPECT_EQ(raw_status(server.port(), "GET /index.html HTTP/1.1\r\nRange: bytes=99999999999-"), 416);
}

// Bodies are compressed once, to gzip only: httplib's own per-request brotli (quality 11) took
// 25 s for three.core.js on a busy machine. A client without gzip gets the plain body.
TEST(Serve, StaticFilesAndJsonAreGzipOnlyWhenAskedAndDecodeToThePlainBody) {
  ArtifactFixture f;
  RunningServer server(f.db);
  for (const char* path : {"/vendor/three.core.js", "/api/campaigns"}) {
    auto client = server.client();
    client.set_decompress(false);
    const auto plain = client.Get(path);
    ASSERT_TRUE(plain);
    EXPECT_FALSE(plain->has_header("Content-Encoding")) << path;
    const auto brotli_only = client.Get(path, {{"Accept-Encoding", "br"}});
    ASSERT_TRUE(brotli_only);
    EXPECT_FALSE(brotli_only->has_header("Content-Encoding")) << path;
    EXPECT_EQ(brotli_only->body, plain->body) << path;
    const auto gzip = client.Get(path, {{"Accept-Encoding", "gzip, deflate, br"}});
    ASSERT_TRUE(gzip);
    if (plain->body.size() < 1024) continue;  // small bodies are not worth compressing
    EXPECT_EQ(gzip->get_header_value("Content-Encoding"), "gzip") << path;
    EXPECT_LT(gzip->body.size(), plain->body.size()) << path;
    auto decoding = server.client();  // httplib's client decodes gzip
    const auto decoded = decoding.Get(path, {{"Accept-Encoding", "gzip"}});
    ASSERT_TRUE(decoded);
    EXPECT_EQ(decoded->body, plain->body) << path;
  }
}

// DNS rebinding: a page of evil.example resolving to 127.0.0.1 sends Host: evil.example.
TEST(Security, OnlyTheBoundHostNamesAreServed) {
  ArtifactFixture f;
  RunningServer server(f.db);
  const std::string port = std::to_string(server.port());
  for (const std::string& host :
       std::vector<std::string>{"evil.example", "evil.example:" + port, "127.0.0.1.evil.example", "", "10.0.0.1"})
    EXPECT_EQ(raw_status(server.port(), "GET /api/campaigns HTTP/1.1", host), 403) << "Host: " << host;
  for (const std::string& host :
       std::vector<std::string>{"127.0.0.1", "127.0.0.1:" + port, "localhost:" + port, "LOCALHOST", "[::1]:" + port})
    EXPECT_EQ(raw_status(server.port(), "GET /api/campaigns HTTP/1.1", host), 200) << "Host: " << host;
}

// A client that starts a request header; send_byte() adds one more byte of it.
class SlowClient {
 public:
  explicit SlowClient(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    const std::string start = "GET /api/campaigns HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
    if (connected_) connected_ = ::send(fd_, start.data(), start.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(start.size());
  }
  ~SlowClient() { ::close(fd_); }
  bool connected() const { return connected_; }
  void send_byte() { connected_ = connected_ && ::send(fd_, "a", 1, MSG_NOSIGNAL) == 1; }
  /// True once the server has closed the connection (recv gives 0 or an error, not "no data yet").
  bool closed_by_server() const {
    char c;
    const ssize_t n = ::recv(fd_, &c, 1, MSG_DONTWAIT);
    return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
  }

 private:
  int fd_;
  bool connected_ = false;
};

// Eight clients trickling a header (one byte every 200 ms) kept 9/9 normal GETs unanswered:
// they held all of httplib's 8 threads, and its per-recv timeout never fired.
TEST(Serve, SlowHeaderClientsLeaveWorkersForFreshRequests) {
  ArtifactFixture f;
  RunningServer server(f.db, 600.0);  // no deadline during this test: the slow clients stay
  std::vector<std::unique_ptr<SlowClient>> slow;
  for (int i = 0; i < 8; ++i) slow.push_back(std::make_unique<SlowClient>(server.port()));
  std::atomic<bool> stop = false;
  std::thread trickle([&] {
    while (!stop) {
      for (auto& c : slow) c->send_byte();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  int answered = 0;
  for (int i = 0; i < 9; ++i) {
    auto client = server.client();
    client.set_read_timeout(20);
    const auto r = client.Get("/api/version");
    answered += r && r->status == 200;
  }
  stop = true;
  trickle.join();
  EXPECT_EQ(answered, 9);
  for (const auto& c : slow) EXPECT_TRUE(c->connected() && !c->closed_by_server()) << "a slow client was cut off early";
}

TEST(Serve, AHeaderNotWholeWithinTheDeadlineClosesTheConnection) {
  ArtifactFixture f;
  RunningServer server(f.db, 0.5);
  SlowClient c(server.port());
  ASSERT_TRUE(c.connected());
  int bytes = 0;
  for (; bytes < 100 && !c.closed_by_server(); ++bytes) {
    c.send_byte();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(c.closed_by_server()) << "still open after a 10 s header";
  auto client = server.client();
  const auto r = client.Get("/api/version");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

TEST(Serve, ATakenPortIsAnError) {
  ArtifactFixture f;
  RunningServer first(f.db);
  ServeOptions options;
  options.database = f.db;
  options.port = first.port();
  options.static_dir = PODIUM_TEST_WEB_DIR;
  Server second(options);
  EXPECT_THROW(second.bind(), base::RuntimeError);
  const auto r =
      podium::testing::run_podium({"serve", "--db", f.db.string(), "--port", std::to_string(first.port())}, f.dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(std::to_string(first.port())), std::string::npos) << r.err;
}

TEST(Security, HostileParametersAreBoundNeverSpliced) {
  TempDir dir;
  testing::run_campaign(dir.path(), testing::landscape_spec("smoke", 20));
  RunningServer server(dir / "podium.db");
  auto client = server.client();
  const auto status = [&](const std::string& path) {
    const auto r = client.Get(path.c_str());
    return r ? r->status : -1;
  };
  // Free-text values reach SQL only as bound parameters: a quote is just a character.
  EXPECT_EQ(status("/api/campaigns/" + testing::url_encode("smoke' OR '1'='1")), 404);
  EXPECT_EQ(status("/api/campaigns/" + testing::url_encode("1 OR 1=1")), 404);
  EXPECT_EQ(status("/api/campaigns/" + testing::url_encode("'; DROP TABLE trials; --")), 404);
  const Json injected = server.get_json("/api/trials/1/metrics?name=" + testing::url_encode("trace' OR '1'='1"));
  EXPECT_EQ(injected.size(), 0u);
  EXPECT_EQ(server.get_json("/api/trials/1/metrics?name=trace").size(), 1u);
  // Typed values are parsed strictly and range-checked.
  for (const char* bad :
       {"/api/campaigns/1/trials?limit=-1", "/api/campaigns/1/trials?limit=100000", "/api/campaigns/1/trials?offset=1%3BDROP",
        "/api/campaigns/1/trials?stage=0%20OR%201%3D1", "/api/campaigns/1/trials?state=done%27%20OR%20%271%27%3D%271",
        "/api/campaigns/1/trials?order=objective%3B%20DROP%20TABLE%20trials",
        "/api/campaigns/1/trials?strategy=99999999999999999999999", "/api/campaigns/1/points?max_points=0",
        "/api/trials/1%20OR%201=1", "/api/trials/0x1", "/api/trials/1/metrics?max_points=abc"})
    EXPECT_EQ(status(bad), 400) << bad;
  const std::string long_name(20000, 'a');
  const int long_status = status("/api/campaigns/" + long_name);
  EXPECT_TRUE(long_status == 404 || long_status == 414) << long_status;  // 414: URI too long
  // Nothing was dropped or changed.
  EXPECT_EQ(store::Store::open(dir / "podium.db", store::Store::Access::read_only)->campaign_trials(1).size(), 20u);
  EXPECT_EQ(server.get_json("/api/campaigns/1/trials")["total"], 20);
}

TEST(Security, ThereAreNoWriteEndpoints) {
  TempDir dir;
  testing::run_campaign(dir.path(), testing::landscape_spec("smoke", 5));
  RunningServer server(dir / "podium.db");
  const auto version = server.get_json("/api/version");
  auto client = server.client();
  for (const char* path : {"/api/campaigns", "/api/campaigns/1", "/api/trials/1", "/index.html"}) {
    for (const auto& r : {client.Post(path, "{}", "application/json"), client.Put(path, "{}", "application/json"),
                          client.Delete(path), client.Patch(path, "{}", "application/json")}) {
      ASSERT_TRUE(r) << path;
      EXPECT_GE(r->status, 400) << path;
    }
  }
  EXPECT_EQ(server.get_json("/api/version"), version);
  EXPECT_EQ(server.get_json("/api/campaigns/1")["state"], "done");
}

// Reads the listening sockets of /proc/net/tcp{,6}: the local addresses bound to `port`.
std::vector<std::string> listen_addresses(int port) {
  std::vector<std::string> out;
  char hex_port[8];
  std::snprintf(hex_port, sizeof hex_port, "%04X", port);
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state;
      fields >> slot >> local >> remote >> state;
      if (state == "0A" && local.substr(local.find(':') + 1) == hex_port) out.push_back(local.substr(0, local.find(':')));
    }
  }
  return out;
}

// `podium serve` as a process: prints its URL, listens on loopback only, stops on SIGTERM.
TEST(Serve, DefaultBindIsLoopbackAndSigtermStopsIt) {
  TempDir dir;
  testing::run_campaign(dir.path(), testing::landscape_spec("smoke", 3));
  const pid_t pid = podium::testing::spawn_podium({"serve", "--port", "0"}, dir.path());
  int port = 0;
  for (int i = 0; i < 200 && port == 0; ++i) {
    std::ifstream in(dir / "spawn.out");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto at = text.find("http://127.0.0.1:");
    if (at != std::string::npos) port = std::stoi(text.substr(at + 17));
    else std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ASSERT_GT(port, 0) << "podium serve printed no URL";
  EXPECT_EQ(listen_addresses(port), std::vector<std::string>{"0100007F"});  // 127.0.0.1, nothing else
  EXPECT_EQ(raw_status(port, "GET /api/campaigns HTTP/1.1"), 200);
  ::kill(pid, SIGTERM);
  EXPECT_EQ(podium::testing::wait_process(pid), 0);
}

TEST(Serve, MissingDatabaseIsAnErrorNotANewFile) {
  TempDir dir;
  const auto r = podium::testing::run_podium({"serve", "--db", "nope.db", "--port", "0"}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nope.db"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "nope.db"));
}

}  // namespace
}  // namespace podium::web_dashboard
