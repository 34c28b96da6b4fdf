#pragma once
// Test support for the dashboard: an in-process Server on a free port, an HTTP client for it, a
// raw request (exact bytes on the wire, for traversal tests), and campaigns run by the real CLI.
#include <httplib.h>

#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "podium/base/json.h"
#include "podium/web_dashboard/server.h"
#include "process.h"

namespace podium::web_dashboard::testing {

using base::Json;

class RunningServer {
 public:
  explicit RunningServer(const std::filesystem::path& database, double header_timeout_s = 5.0) {
    ServeOptions options;
    options.database = database;
    options.header_timeout_s = header_timeout_s;
    options.port = 0;
    options.static_dir = PODIUM_TEST_WEB_DIR;
    server_ = std::make_unique<Server>(options);
    port_ = server_->bind();
    thread_ = std::thread([this] { server_->run(); });
  }
  ~RunningServer() {
    server_->stop();
    thread_.join();
  }
  int port() const { return port_; }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(30);
    return c;
  }
  /// GET path; the body parsed as JSON (status in *status if given).
  Json get_json(const std::string& path, int* status = nullptr) const {
    auto c = client();
    auto r = c.Get(path.c_str());
    if (!r) throw std::runtime_error("GET " + path + ": no response");
    if (status) *status = r->status;
    return Json::parse(r->body);
  }

 private:
  std::unique_ptr<Server> server_;
  int port_ = 0;
  std::thread thread_;
};

/// Sends `request_line` (e.g. "GET /../x HTTP/1.1") verbatim with the given Host header; returns
/// the response's status code.
int raw_status(int port, const std::string& request_line, const std::string& host = "127.0.0.1");

/// Percent-encodes every byte but RFC 3986's unreserved characters.
std::string url_encode(const std::string& text);

/// Writes spec to dir/spec.json, submits it and runs the scheduler to the end; returns the id.
/// `podium run` must exit `exit_code` (1: the campaign is meant to end failed).
std::int64_t run_campaign(const std::filesystem::path& dir, const Json& spec, int exit_code = 0);

/// A one-stage landscape smoke campaign with `trials` trials and result.json artifacts.
Json landscape_spec(const std::string& name, int trials, const Json& extra_config = Json::object());

/// A one-stage campaign of the test-only web_replay_fixture task (trajectory artifacts).
Json replay_fixture_spec(const std::string& name, int trials);

}  // namespace podium::web_dashboard::testing
