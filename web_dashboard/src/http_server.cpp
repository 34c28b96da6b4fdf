#include "http_server.h"

#include <sys/socket.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <charconv>
#include <chrono>
#include <mutex>

#include "podium/base/error.h"

namespace podium::web_dashboard {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

std::optional<std::string> Request::param(const std::string& name) const {
  const auto it = params.find(name);
  return it == params.end() ? std::nullopt : std::optional(it->second);
}

void Response::set_text(std::string body, std::string mime) {
  text = std::make_shared<const std::string>(std::move(body));
  content_type = std::move(mime);
}

void Response::set_file(const std::filesystem::path& path, std::string mime) {
  file = std::make_shared<std::ifstream>(path, std::ios::binary);
  if (!*file) throw base::RuntimeError(path.string() + ": cannot be read");
  file_size = std::filesystem::file_size(path);
  content_type = std::move(mime);
}

std::string percent_decode(const std::string& text, bool plus_is_space) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    unsigned value = 0;
    if (text[i] == '%' && i + 2 < text.size() &&
        std::from_chars(text.data() + i + 1, text.data() + i + 3, value, 16).ptr == text.data() + i + 3) {
      out += static_cast<char>(value);
      i += 2;
    } else {
      out += plus_is_space && text[i] == '+' ? ' ' : text[i];
    }
  }
  return out;
}

ByteRange byte_range(const std::string& range, std::uintmax_t size) {
  ByteRange whole;
  if (range.rfind("bytes=", 0) != 0 || range.find(',') != std::string::npos) return whole;
  const std::string spec = range.substr(6);
  const auto dash = spec.find('-');
  if (dash == std::string::npos) return whole;
  const auto number = [](const std::string& s, std::uintmax_t& v) {
    return !s.empty() && std::from_chars(s.data(), s.data() + s.size(), v).ptr == s.data() + s.size();
  };
  std::uintmax_t first = 0, last = 0;
  const std::string a = spec.substr(0, dash), b = spec.substr(dash + 1);
  if (a.empty()) {  // the last b bytes
    if (!number(b, last)) return whole;
    if (last == 0 || size == 0) return {ByteRange::Kind::unsatisfiable};
    const std::uintmax_t n = std::min(last, size);
    return {ByteRange::Kind::part, size - n, n};
  }
  if (!number(a, first) || (!b.empty() && (!number(b, last) || last < first))) return whole;
  if (first >= size) return {ByteRange::Kind::unsatisfiable};
  const std::uintmax_t end = b.empty() ? size : std::min(last + 1, size);
  return {ByteRange::Kind::part, first, end - first};
}

namespace {

constexpr std::uint32_t kHeaderLimit = 32 * 1024;
constexpr std::uint64_t kBodyLimit = 64 * 1024;
constexpr std::size_t kChunk = 256 * 1024;

Clock::duration seconds(double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); }

class Connection;

// Open connections by peer address; the I/O thread admits and evicts, a connection that ends
// leaves from whichever thread drops it last.
class Registry {
 public:
  explicit Registry(int per_client) : per_client_(per_client) {}

  enum class Admit { yes, no };
  // Admits a new connection from `client`, closing the longest-waiting one when at the bound.
  Admit admit(const std::string& client, std::shared_ptr<Connection>& evicted);
  void add(std::uint64_t id, const std::string& client, std::weak_ptr<Connection> connection) {
    std::lock_guard lock(mutex_);
    entries_[id] = {client, Clock::time_point::max(), std::move(connection)};
    ++count_[client];
  }
  void remove(std::uint64_t id) {
    std::lock_guard lock(mutex_);
    const auto it = entries_.find(id);
    if (it == entries_.end()) return;
    if (--count_[it->second.client] == 0) count_.erase(it->second.client);
    entries_.erase(it);
  }
  // The connection waits for a request header from now on (waiting), or is busy.
  void set_waiting(std::uint64_t id, bool waiting) {
    std::lock_guard lock(mutex_);
    if (const auto it = entries_.find(id); it != entries_.end())
      it->second.waiting_since = waiting ? Clock::now() : Clock::time_point::max();
  }

 private:
  struct Entry {
    std::string client;
    Clock::time_point waiting_since;  // max() while busy
    std::weak_ptr<Connection> connection;
  };
  int per_client_;
  std::mutex mutex_;
  std::map<std::uint64_t, Entry> entries_;
  std::map<std::string, int> count_;
};

struct Shared {
  Shared(HttpServerOptions o, HttpServer::Handler h, asio::thread_pool& pool)
      : options(std::move(o)), handler(std::move(h)), registry(options.connections_per_client), handlers(pool) {}
  HttpServerOptions options;
  HttpServer::Handler handler;
  Registry registry;
  asio::thread_pool& handlers;
};

// One client connection: read a request (header, then body), hand it to the handler pool, write
// the response in chunks, and again while the client keeps the connection alive.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket socket, Shared& shared, std::uint64_t id, std::string client)
      : stream_(std::move(socket)), shared_(shared), id_(id), client_(std::move(client)) {}
  ~Connection() { shared_.registry.remove(id_); }

  void start() {
    shared_.registry.add(id_, client_, weak_from_this());
    read_header();
  }
  // Closes the socket: a pending read ends with an error, and the connection with it.
  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_.close();
  }

 private:
  void read_header() {
    shared_.registry.set_waiting(id_, true);
    parser_.emplace();
    parser_->header_limit(kHeaderLimit);
    parser_->body_limit(kBodyLimit);
    stream_.expires_after(seconds(shared_.options.header_timeout_s));
    http::async_read_header(stream_, buffer_, *parser_,
                            [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  void on_header(beast::error_code ec) {
    shared_.registry.set_waiting(id_, false);
    if (ec) return fail(ec);
    if (parser_->is_done()) return dispatch();
    stream_.expires_after(seconds(shared_.options.body_timeout_s));
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code e, std::size_t) {
      if (e) return self->fail(e);
      self->dispatch();
    });
  }

  // A read that failed: a malformed or oversized request is answered, anything else (the client
  // left, a deadline passed, the server stops) just closes.
  void fail(beast::error_code ec) {
    keep_alive_ = false;
    Response res;
    if (ec == http::error::header_limit) res.status = 431;
    else if (ec == http::error::body_limit) res.status = 413;
    else if (ec.category() == beast::error_code(http::error::bad_method).category() && ec != http::error::end_of_stream &&
             ec != http::error::partial_message)
      res.status = 400;
    else return close();
    res.set_text(std::string(http::obsolete_reason(http::int_to_status(static_cast<unsigned>(res.status)))) + "\n",
                 "text/plain; charset=utf-8");
    write(std::move(res), false);
  }

  void dispatch() {
    const auto& message = parser_->get();
    keep_alive_ = message.keep_alive();
    auto req = std::make_shared<Request>();
    req->method = std::string(message.method_string());
    const std::string target(message.target());
    const auto query = target.find('?');
    req->path = percent_decode(target.substr(0, query), false);
    if (query != std::string::npos) {
      for (std::size_t from = query + 1; from <= target.size();) {
        const auto amp = std::min(target.find('&', from), target.size());
        const std::string pair = target.substr(from, amp - from);
        const auto eq = pair.find('=');
        if (!pair.empty())
          req->params.emplace(percent_decode(pair.substr(0, eq), true),
                              eq == std::string::npos ? "" : percent_decode(pair.substr(eq + 1), true));
        from = amp + 1;
      }
    }
    req->host = std::string(message[http::field::host]);
    req->accept_encoding = std::string(message[http::field::accept_encoding]);
    range_ = std::string(message[http::field::range]);
    req->has_range = !range_.empty();
    const bool head = message.method() == http::verb::head;
    asio::post(shared_.handlers, [self = shared_from_this(), req, head] {
      Response res = self->shared_.handler(*req);
      asio::post(self->stream_.get_executor(),
                 [self, res = std::move(res), head]() mutable { self->write(std::move(res), head); });
    });
  }

  // The status line and headers; a 200 body cut to the requested range first.
  void write(Response res, bool head) {
    const bool has_body = res.text || res.file;
    body_size_ = res.text ? res.text->size() : res.file ? res.file_size : 0;
    body_first_ = 0;
    if (has_body && res.status == 200 && res.ranges && !range_.empty()) {
      const ByteRange r = byte_range(range_, body_size_);
      if (r.kind == ByteRange::Kind::unsatisfiable) {
        res.set_header("Content-Range", "bytes */" + std::to_string(body_size_));
        res.status = 416;
        res.text.reset();
        res.file.reset();
        body_size_ = 0;
      } else if (r.kind == ByteRange::Kind::part) {
        res.set_header("Content-Range", "bytes " + std::to_string(r.first) + "-" + std::to_string(r.first + r.length - 1) + "/" +
                                            std::to_string(body_size_));
        res.status = 206;
        body_first_ = r.first;
        body_size_ = r.length;
      }
    }
    if (has_body && res.ranges && res.status == 200) res.set_header("Accept-Ranges", "bytes");
    head_ = "HTTP/1.1 " + std::to_string(res.status) + " " +
            std::string(http::obsolete_reason(http::int_to_status(static_cast<unsigned>(res.status)))) + "\r\n";
    for (const auto& [name, value] : shared_.options.default_headers) head_ += name + ": " + value + "\r\n";
    for (const auto& [name, value] : res.headers) head_ += name + ": " + value + "\r\n";
    head_ += "Content-Type: " + res.content_type + "\r\nContent-Length: " + std::to_string(body_size_) + "\r\n";
    head_ += keep_alive_ ? "Connection: keep-alive\r\n\r\n" : "Connection: close\r\n\r\n";
    if (head) body_size_ = 0;
    response_ = std::move(res);
    sent_ = 0;
    write_chunk(true);
  }

  // The next piece of the response (the header with the first), then the next read or the end.
  void write_chunk(bool first) {
    if (!first && sent_ >= body_size_) return finish();
    const std::size_t n = static_cast<std::size_t>(std::min<std::uintmax_t>(kChunk, body_size_ - sent_));
    std::vector<asio::const_buffer> buffers;
    if (first) buffers.push_back(asio::buffer(head_));
    if (n > 0 && response_.text) {
      buffers.push_back(asio::buffer(response_.text->data() + body_first_ + sent_, n));
    } else if (n > 0) {
      chunk_.resize(n);
      response_.file->seekg(static_cast<std::streamoff>(body_first_ + sent_));
      response_.file->read(chunk_.data(), static_cast<std::streamsize>(n));
      if (response_.file->gcount() != static_cast<std::streamsize>(n)) return close();  // the file shrank
      buffers.push_back(asio::buffer(chunk_));
    }
    sent_ += n;
    stream_.expires_after(seconds(shared_.options.write_timeout_s));
    asio::async_write(stream_, buffers, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->write_chunk(false);
    });
  }

  void finish() {
    response_ = Response();
    if (keep_alive_) return read_header();
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream_.close();
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  Shared& shared_;
  std::uint64_t id_;
  std::string client_;
  bool keep_alive_ = true;
  std::string range_;
  Response response_;
  std::string head_;
  std::vector<char> chunk_;
  std::uintmax_t body_first_ = 0, body_size_ = 0, sent_ = 0;
};

Registry::Admit Registry::admit(const std::string& client, std::shared_ptr<Connection>& evicted) {
  std::lock_guard lock(mutex_);
  if (count_[client] < per_client_) return Admit::yes;
  auto oldest = entries_.end();
  for (auto it = entries_.begin(); it != entries_.end(); ++it)
    if (it->second.client == client && it->second.waiting_since != Clock::time_point::max() &&
        (oldest == entries_.end() || it->second.waiting_since < oldest->second.waiting_since))
      oldest = it;
  if (oldest == entries_.end()) return Admit::no;
  evicted = oldest->second.connection.lock();
  if (--count_[client] == 0) count_.erase(client);
  entries_.erase(oldest);
  return Admit::yes;
}

}  // namespace

// Destroyed in reverse order: the handler pool (and the connections its abandoned jobs hold)
// before the I/O context their sockets belong to, the registry they leave last.
struct HttpServer::Impl {
  Impl(HttpServerOptions o, Handler h)
      : shared(std::move(o), std::move(h), handlers),
        handlers(static_cast<std::size_t>(std::max(1, shared.options.handler_threads))) {}
  Shared shared;  // holds a reference to `handlers`, used only once requests arrive
  asio::io_context io;
  tcp::acceptor acceptor{io};
  asio::steady_timer retry{io};
  asio::thread_pool handlers;
  std::uint64_t next_id = 0;

  void accept() {
    acceptor.async_accept(io, [this](beast::error_code ec, tcp::socket socket) {
      if (ec == asio::error::operation_aborted || !acceptor.is_open()) return;
      if (ec) {  // out of descriptors, say: try again shortly instead of spinning
        retry.expires_after(std::chrono::milliseconds(100));
        retry.async_wait([this](beast::error_code) { accept(); });
        return;
      }
      admit(std::move(socket));
      accept();
    });
  }

  void admit(tcp::socket socket) {
    beast::error_code ec;
    const auto peer = socket.remote_endpoint(ec);
    if (ec) return;
    socket.set_option(tcp::no_delay(true), ec);
    const std::string client = peer.address().to_string();
    std::shared_ptr<Connection> evicted;
    if (shared.registry.admit(client, evicted) == Registry::Admit::no) {
      static const std::string kBusy =
          "HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nContent-Length: 42\r\nConnection: close\r\n\r\n"
          "too many connections from this address\r\n\r\n";
      ::send(socket.native_handle(), kBusy.data(), kBusy.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
      return;
    }
    if (evicted) evicted->close();
    std::make_shared<Connection>(std::move(socket), shared, next_id++, client)->start();
  }
};

HttpServer::HttpServer(HttpServerOptions options, Handler handler)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(handler))) {}

HttpServer::~HttpServer() {
  impl_->io.stop();
  impl_->shared.handlers.stop();
  impl_->shared.handlers.join();
}

int HttpServer::bind(const std::string& host, int port) {
  beast::error_code ec;
  tcp::resolver resolver(impl_->io);
  const auto endpoints =
      resolver.resolve(host, std::to_string(port), tcp::resolver::passive | tcp::resolver::numeric_service, ec);
  if (ec) return -1;
  for (const auto& entry : endpoints) {
    auto& a = impl_->acceptor;
    a.open(entry.endpoint().protocol(), ec);
    if (!ec) a.set_option(asio::socket_base::reuse_address(true), ec);
    if (!ec) a.bind(entry.endpoint(), ec);
    if (!ec) a.listen(asio::socket_base::max_listen_connections, ec);
    if (!ec) return a.local_endpoint().port();
    a.close(ec);
  }
  return -1;
}

void HttpServer::run() {
  impl_->accept();
  impl_->io.run();
}

void HttpServer::stop() { impl_->io.stop(); }

}  // namespace podium::web_dashboard
