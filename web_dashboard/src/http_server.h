#pragma once
// The dashboard's HTTP transport: an asynchronous server (Boost.Beast on Boost.Asio).
// - Reading a request holds no thread: one I/O thread reads every connection's header and body
//   as bytes arrive, so clients that send a header one byte at a time cost a socket each, not a
//   worker. A whole request is handed to a small pool of handler threads (store queries block).
// - Deadlines: a request header must arrive whole within header_timeout_s of the server starting
//   to wait for it (accept, or the previous response sent), a body within body_timeout_s, each
//   response chunk must be taken by the client within write_timeout_s; otherwise the connection
//   is closed.
// - Bound per client: at most connections_per_client open connections per peer address. A new
//   connection beyond it closes that address's connection that has waited longest for a header;
//   if none is waiting (all are being answered), the new one gets 503 and is closed.
// - Limits: header 32 kB (431 beyond), body 64 kB (413 beyond), one byte range (206/416).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace podium::web_dashboard {

/// A request as the routes see it.
struct Request {
  std::string method;                              ///< "GET", "HEAD", "POST", ...
  std::string path;                                ///< percent-decoded, without the query
  std::multimap<std::string, std::string> params;  ///< the query, decoded ("+" is a space)
  std::string host;                                ///< the Host header
  std::string accept_encoding;                     ///< the Accept-Encoding header
  bool has_range = false;                          ///< a Range header was sent
  std::vector<std::string> matches;                ///< the route's capture groups, [0] the whole path

  /// The first value of query parameter `name`, if given.
  std::optional<std::string> param(const std::string& name) const;
};

/// A response: status, headers and a body held in memory (shared, not copied) or read from a
/// file as it is sent. A 200 body may be cut to a requested byte range by the server.
struct Response {
  int status = 200;
  std::vector<std::pair<std::string, std::string>> headers;  ///< besides Content-Type/-Length
  std::string content_type = "text/plain; charset=utf-8";
  std::shared_ptr<const std::string> text;  ///< the body, or null
  std::shared_ptr<std::ifstream> file;      ///< or a file of file_size bytes
  std::uintmax_t file_size = 0;
  bool ranges = true;  ///< false: the body is an encoding of the resource (gzip), ranges do not apply

  void set_header(std::string name, std::string value) { headers.emplace_back(std::move(name), std::move(value)); }
  void set_text(std::string body, std::string mime);
  /// Opens `path` (base::RuntimeError if it cannot be read).
  void set_file(const std::filesystem::path& path, std::string mime);
};

struct HttpServerOptions {
  double header_timeout_s = 5.0;
  double body_timeout_s = 5.0;
  double write_timeout_s = 30.0;
  int connections_per_client = 128;
  int handler_threads = 8;
  std::vector<std::pair<std::string, std::string>> default_headers;  ///< on every response
};

class HttpServer {
 public:
  using Handler = std::function<Response(Request&)>;

  HttpServer(HttpServerOptions options, Handler handler);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// Listens on host:port (0: any free port; SO_REUSEADDR, never SO_REUSEPORT); returns the
  /// port, or -1 if no address of `host` can be bound.
  int bind(const std::string& host, int port);
  /// Serves on the calling thread until stop().
  void run();
  /// Thread-safe; run() returns soon after (a stop before run() makes run() return at once).
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Decodes %XX escapes (invalid ones stay as they are); `plus_is_space` for query strings.
std::string percent_decode(const std::string& text, bool plus_is_space);

/// What a Range header asks of a body of `size` bytes. Only a single byte range is served
/// ("bytes=a-b", "bytes=a-", "bytes=-n"); anything else is ignored and the whole body sent, as
/// RFC 9110 §14.2 allows.
struct ByteRange {
  enum class Kind { whole, part, unsatisfiable } kind = Kind::whole;
  std::uintmax_t first = 0, length = 0;  ///< part: the bytes [first, first + length)
};
ByteRange byte_range(const std::string& range, std::uintmax_t size);

}  // namespace podium::web_dashboard
