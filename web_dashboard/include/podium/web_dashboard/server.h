#pragma once
/// `podium serve`: a read-only HTTP dashboard on a Podium database (docs/architecture.md "The dashboard").
///
/// Serves the JSON API (`/api/...`, documented in the top-level README "The dashboard") and the
/// static front end, both GET only. The database is opened read-only; every request borrows a
/// connection from a small pool and reads in one short read transaction that ends before the
/// response is sent, so no read transaction outlives a request and a running scheduler (WAL
/// mode) is never blocked. Server threads run at a lower CPU priority (nice +10) than the scheduler. API responses are cached by
/// URL and database version (SQLite's data_version): repeated requests cost nothing until a commit; a campaign's summary is also
/// kept until its own change token changes (src/api.h SummaryCache), so commits to other campaigns leave it valid. The transport
/// is asynchronous (src/http_server.h): a slow client holds a socket, never a thread. A request header must arrive whole within
/// header_timeout_s of the server waiting for it, a body within as long; a peer address holds at most connections_per_client
/// connections; the Host header must name the bound address (src/host_rule.h); a taken port is an error.
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>

namespace podium::web_dashboard {

struct ServeOptions {
  std::filesystem::path database = "podium.db";
  std::string host = "127.0.0.1";    ///< localhost only unless asked otherwise
  int port = 8080;                   ///< 0: any free port (see Server::port())
  std::filesystem::path static_dir;  ///< the built front end (index.html, vendor/...)
  bool cache = true;                 ///< reuse an API response while the database (a summary: its campaign) is unchanged
  double header_timeout_s = 5.0;     ///< a request header (and its body) must arrive whole within this time
  int connections_per_client = 128;  ///< open connections per peer address (the longest-waiting one makes room)
};

class Server {
 public:
  /// Opens the database (read-only) and loads the front end into memory. Throws
  /// base::RuntimeError if the database cannot be opened, base::UserError if static_dir has no
  /// index.html.
  explicit Server(const ServeOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds the listening socket; returns the port (the chosen one when options.port is 0).
  /// Throws base::RuntimeError if the address cannot be bound.
  int bind();
  /// Serves until stop() is called (from another thread or a signal handler's thread).
  void run();
  void stop();
  int port() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `podium serve`: binds, prints the URL on `out`, serves until SIGINT or SIGTERM; returns 0.
int serve(const ServeOptions& options, std::ostream& out);

/// The front end next to an installed or built `podium` binary: <bin>/../share/podium/web.
std::filesystem::path default_static_dir(const std::filesystem::path& podium_binary);

}  // namespace podium::web_dashboard
