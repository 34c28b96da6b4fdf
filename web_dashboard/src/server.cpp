#include "podium/web_dashboard/server.h"

#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "api.h"
#include "encoded_body.h"
#include "host_rule.h"
#include "http_server.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/store/writer_lock.h"
#include "pool.h"
#include "static_files.h"

namespace podium::web_dashboard {

namespace fs = std::filesystem;

namespace {

const std::vector<std::pair<std::string, std::string>> kSecurityHeaders = {
    {"X-Content-Type-Options", "nosniff"},
    {"X-Frame-Options", "DENY"},
    // Everything comes from this server: no CDN, no inline script, nothing framed.
    {"Content-Security-Policy", "default-src 'self'; img-src 'self' data:; style-src 'self' 'unsafe-inline'"},
    {"Referrer-Policy", "no-referrer"}};

std::int64_t parse_int(const std::string& text, const char* what, std::int64_t low, std::int64_t high) {
  std::int64_t value = 0;
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || value < low || value > high)
    throw HttpError(400, std::string(what) + ": \"" + text + "\" is not an integer in [" + std::to_string(low) + ", " +
                             std::to_string(high) + "]");
  return value;
}

std::optional<std::string> param(const Request& req, const char* name) { return req.param(name); }

std::int64_t int_param(const Request& req, const char* name, std::int64_t fallback, std::int64_t low, std::int64_t high) {
  const auto text = param(req, name);
  return text ? parse_int(*text, name, low, high) : fallback;
}

store::TrialFilter trial_filter(const Request& req) {
  store::TrialFilter f;
  if (auto s = param(req, "stage")) f.stage_index = static_cast<int>(parse_int(*s, "stage", 0, 1'000'000));
  if (auto s = param(req, "state")) {
    static const std::set<std::string> kStates = {"pending", "running", "done", "failed", "interrupted", "cancelled"};
    if (!kStates.count(*s)) throw HttpError(400, "state: \"" + *s + "\" is not a trial state");
    f.state = *s;
  }
  if (auto s = param(req, "strategy")) f.strategy = parse_int(*s, "strategy", INT64_MIN, INT64_MAX);
  f.offset = int_param(req, "offset", 0, 0, INT64_MAX);
  f.limit = int_param(req, "limit", 100, 1, 1000);
  if (auto s = param(req, "order")) {
    if (*s == "index") f.order = store::TrialFilter::Order::index;
    else if (*s == "objective") f.order = store::TrialFilter::Order::objective;
    else if (*s == "finished") f.order = store::TrialFilter::Order::finished;
    else throw HttpError(400, "order: \"" + *s + "\" is not one of index, objective, finished");
  }
  if (auto s = param(req, "desc")) f.descending = *s == "1" || *s == "true";
  return f;
}

void send_json(Response& res, const Json& body) {
  res.set_header("Cache-Control", "no-store");
  res.set_text(body.dump(), "application/json");
}

// A file, read as it is sent (checkpoints can be large); `download`: the name it is saved as
// (empty: shown inline).
void send_file(Response& res, const fs::path& file, const std::string& mime, const std::string& download) {
  if (!download.empty()) {
    std::string name = download;
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
    res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
  }
  res.set_file(file, mime);
}

// Response bodies by URL, valid for one database version. Bounded: when full, it starts over.
class ResponseCache {
 public:
  std::shared_ptr<const EncodedBody> find(const std::string& key, std::int64_t version) {
    std::lock_guard lock(mutex_);
    const auto it = entries_.find(key);
    return it != entries_.end() && it->second.first == version ? it->second.second : nullptr;
  }
  void put(const std::string& key, std::int64_t version, std::shared_ptr<const EncodedBody> body) {
    std::lock_guard lock(mutex_);
    const std::size_t size = body->plain.size() + body->gzip.size();
    if (bytes_ + size > kMaxBytes) {
      entries_.clear();
      bytes_ = 0;
    }
    bytes_ += size;
    entries_[key] = {version, std::move(body)};
  }

 private:
  static constexpr std::size_t kMaxBytes = 64u << 20;
  std::mutex mutex_;
  std::map<std::string, std::pair<std::int64_t, std::shared_ptr<const EncodedBody>>> entries_;
  std::size_t bytes_ = 0;
};

// A response body: a document, or JSON text an endpoint wrote itself.
std::string body_text(const Json& document) { return document.dump(); }
std::string body_text(std::string text) { return text; }

// The cache key: path and parameters in a canonical order.
std::string cache_key(const Request& req) {
  std::string key = req.path;
  for (const auto& [name, value] : req.params) key += "\n" + name + "=" + value;  // a multimap: sorted
  return key;
}

}  // namespace

using RouteHandler = std::function<void(const Request&, Response&)>;

struct Server::Impl {
  ServeOptions options;
  QueriesPool pool;
  std::mutex watch_mutex;
  std::unique_ptr<store::Queries> watch;  // one connection, so its data_version is one sequence
  StaticFiles files;
  ResponseCache cache;
  SummaryCache summaries;                                    // per campaign, by its own change token (api.h)
  std::vector<std::pair<std::regex, RouteHandler>> routes_;  // GET (and HEAD); the first match answers
  HttpServer http;
  int port = 0;

  explicit Impl(const ServeOptions& o)
      : options(o),
        pool(o.database),
        watch(store::Queries::open(o.database)),
        files(o.static_dir),
        summaries(o.cache),
        http(http_options(o), [this](Request& req) { return handle(req); }) {}

  static HttpServerOptions http_options(const ServeOptions& o) {
    HttpServerOptions h;
    h.header_timeout_s = o.header_timeout_s;
    h.body_timeout_s = o.header_timeout_s;
    h.connections_per_client = o.connections_per_client;
    h.default_headers = kSecurityHeaders;
    return h;
  }

  // Every request: the Host rule, GET or HEAD only, then the first route whose pattern matches.
  Response handle(Request& req) {
    Response res;
    if (!allowed_host(req.host, options.host)) {
      res.status = 403;
      res.set_text("Host \"" + req.host + "\" is not this dashboard's address\n", "text/plain");
    } else if (req.method != "GET" && req.method != "HEAD") {
      res.status = 405;  // read-only
      res.set_header("Allow", "GET, HEAD");
      res.set_text("the dashboard is read-only (GET and HEAD only)\n", "text/plain");
    } else {
      std::smatch m;
      for (const auto& [pattern, handler] : routes_) {
        if (!std::regex_match(req.path, m, pattern)) continue;
        req.matches.assign(m.begin(), m.end());
        handler(req, res);
        break;
      }
    }
    return res;
  }

  void get(const char* pattern, RouteHandler handler) { routes_.emplace_back(std::regex(pattern), std::move(handler)); }

  // Runs a handler; HttpError and any other exception become a JSON error response.
  template <class Fn>
  RouteHandler api(Fn fn) {
    return [fn](const Request& req, Response& res) {
      try {
        fn(req, res);
      } catch (const HttpError& e) {
        res = Response();
        res.status = e.status;
        send_json(res, {{"error", e.what()}});
      } catch (const std::exception& e) {
        res = Response();
        res.status = 500;
        send_json(res, {{"error", e.what()}});
      }
    };
  }

  // SQLite's data_version, with whether a scheduler holds the database: a scheduler that dies
  // changes what pages show ("stopped") without a commit, so it must change the version too.
  std::int64_t data_version() {
    std::lock_guard lock(watch_mutex);
    return 2 * watch->data_version() + (store::WriterLock::held(options.database) ? 1 : 0);
  }

  // A JSON endpoint: build(req, queries) makes the document (or its text); the body is reused while the
  // database version is unchanged. The version is read before the query, so a cached body is
  // never older than its version.
  template <class Build>
  RouteHandler json(Build build) {
    return api([this, build](const Request& req, Response& res) {
      const std::int64_t version = data_version();
      const std::string key = cache_key(req);
      auto body = options.cache ? cache.find(key, version) : nullptr;
      if (!body) {
        auto q = pool.acquire();
        body = EncodedBody::make(body_text(build(req, *q)));
        if (options.cache) cache.put(key, version, body);
      }
      res.set_header("Cache-Control", "no-store");
      send_body(req, res, body, "application/json");
    });
  }

  void routes() {
    get("/api/version", api([this](const Request&, Response& res) { send_json(res, {{"data_version", data_version()}}); }));
    get("/api/campaigns", json([](const Request&, const store::Queries& q) { return campaign_list(q, store::now_unix_s()); }));
    get(R"(/api/campaigns/([^/]+))", json([](const Request& req, const store::Queries& q) {
          return campaign_detail(q, resolve_campaign(q, req.matches[1]), store::now_unix_s());
        }));
    get(R"(/api/campaigns/([^/]+)/trials)", json([](const Request& req, const store::Queries& q) {
          const auto filter = trial_filter(req);
          return trial_page(q, resolve_campaign(q, req.matches[1]), filter);
        }));
    get(R"(/api/campaigns/([^/]+)/points)", json([](const Request& req, const store::Queries& q) {
          const auto max_points = int_param(req, "max_points", 5000, 1, 1'000'000);
          return scatter_points(q, resolve_campaign(q, req.matches[1]), max_points);
        }));
    get(R"(/api/campaigns/([^/]+)/strategies)",
        json([](const Request& req, const store::Queries& q) { return strategy_table(q, resolve_campaign(q, req.matches[1])); }));
    get(R"(/api/campaigns/([^/]+)/summary)", json([this](const Request& req, const store::Queries& q) {
          return summary_document(q, summaries, resolve_campaign(q, req.matches[1]));
        }));
    get("/api/compare", json([this](const Request& req, const store::Queries& q) {
          const auto campaigns = param(req, "campaigns");
          if (!campaigns) throw HttpError(400, "campaigns: missing (compare?campaigns=ID,ID,...)");
          return comparison_document(q, summaries, *campaigns);
        }));
    get(R"(/api/campaigns/([^/]+)/events)", json([](const Request& req, const store::Queries& q) {
          const auto last = int_param(req, "last", 200, 1, 10000);
          return campaign_events(q, resolve_campaign(q, req.matches[1]), static_cast<std::size_t>(last));
        }));
    get(R"(/api/trials/([^/]+))", json([](const Request& req, const store::Queries& q) {
          return trial_detail(q, parse_int(req.matches[1], "trial", 1, INT64_MAX));
        }));
    get(R"(/api/trials/([^/]+)/metrics)", json([](const Request& req, const store::Queries& q) {
          const auto id = parse_int(req.matches[1], "trial", 1, INT64_MAX);
          const auto max_points = int_param(req, "max_points", 1000, 1, 1'000'000);
          return metric_series(q, id, max_points, param(req, "name"));
        }));
    get(R"(/api/trials/([^/]+)/artifacts/([^/]+))", api([this](const Request& req, Response& res) {
          const auto id = parse_int(req.matches[1], "trial", 1, INT64_MAX);
          const auto index = static_cast<std::size_t>(parse_int(req.matches[2], "artifact", 0, 1'000'000));
          auto q = pool.acquire();
          send_file(res, artifact_file(*q, options.database, id, index), "application/octet-stream",
                    artifact_download_name(*q, id, index));
        }));
    get(R"(/api/trials/([^/]+)/log)", api([this](const Request& req, Response& res) {
          const auto id = parse_int(req.matches[1], "trial", 1, INT64_MAX);
          send_file(res, trial_log_file(*pool.acquire(), options.database, id), "text/plain; charset=utf-8", "");
        }));
    // The style curves' targets and achieved features, parsed and checked (api.h).
    get(R"(/api/trials/([^/]+)/curves)", json([this](const Request& req, const store::Queries& q) {
          return style_curves_document(q, options.database, parse_int(req.matches[1], "trial", 1, INT64_MAX));
        }));
    get(R"(/api/trials/([^/]+)/trajectory)", api([this](const Request& req, Response& res) {
          const auto id = parse_int(req.matches[1], "trial", 1, INT64_MAX);
          // ?artifact=NAME picks another recorded motion of the trial (trajectory_fast, ...).
          const std::string name = req.param("artifact").value_or("trajectory");
          if (name.rfind("trajectory", 0) != 0)
            throw HttpError(400, "artifact \"" + name + "\" is not a trajectory (its name starts with trajectory)");
          auto q = pool.acquire();
          send_file(res, artifact_file(*q, options.database, id, artifact_index(*q, id, name)), "application/x-ndjson",
                    "");  // sim/'s JSON-lines trajectory file
        }));
    get(R"(/api/.*)", api([](const Request& req, Response&) -> void { throw HttpError(404, "no endpoint " + req.path); }));
    get(R"(/(.*))", [this](const Request& req, Response& res) {
      const std::string path = req.matches[1].empty() ? "index.html" : req.matches[1];
      if (const auto* f = files.find(path)) {
        res.set_header("Cache-Control", "no-cache");
        send_body(req, res, f->body, f->mime);
      } else {
        res.status = 404;
        res.set_text("not found\n", "text/plain");
      }
    });
  }
};

Server::Server(const ServeOptions& options) : impl_(std::make_unique<Impl>(options)) { impl_->routes(); }
Server::~Server() = default;

int Server::bind() {
  const auto& o = impl_->options;
  impl_->port = impl_->http.bind(o.host, o.port);
  if (impl_->port <= 0)
    throw base::RuntimeError("podium serve: cannot listen on " + o.host + ":" + std::to_string(o.port) +
                             " (address in use or not local?)");
  return impl_->port;
}

void Server::run() { impl_->http.run(); }
void Server::stop() { impl_->http.stop(); }
int Server::port() const { return impl_->port; }

fs::path default_static_dir(const fs::path& podium_binary) {
  return podium_binary.parent_path().parent_path() / "share" / "podium" / "web";
}

int serve(const ServeOptions& options, std::ostream& out) {
  // The dashboard is an observer: on a busy machine the scheduler and its trials come first.
  // Set before any thread starts, so every server thread inherits it.
  ::setpriority(PRIO_PROCESS, 0, std::min(19, ::getpriority(PRIO_PROCESS, 0) + 10));
  // Signals are taken by a thread of our own, so stopping is ordinary code, not a handler.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  Server server(options);
  const int port = server.bind();
  out << "podium serve: http://" << options.host << ":" << port << "/ (database " << options.database.string() << ", read-only)"
      << std::endl;
  std::thread waiter([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    server.stop();
  });
  server.run();
  // Wakes the waiter if run() ended on its own. SIGTERM is blocked in every thread and the waiter
  // takes it in sigwait, so it ends no thread and no process.
  pthread_kill(waiter.native_handle(), SIGTERM);  // NOLINT(bugprone-bad-signal-to-kill-thread): see above
  waiter.join();
  return 0;
}

}  // namespace podium::web_dashboard
