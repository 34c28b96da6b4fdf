#include "guarded_http.h"

#include <netdb.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

namespace podium::web_dashboard {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// "name:port" -> "name"; "[::1]:8080" -> "[::1]"; "name" -> "name".
std::string host_name(const std::string& header) {
  if (!header.empty() && header.front() == '[') return header.substr(0, header.find(']') + 1);
  return header.substr(0, header.find(':'));
}

bool is_loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// "address:port" of a socket's local or remote end, as httplib writes req.remote_addr/port.
std::string endpoint(const sockaddr_storage& addr, socklen_t length) {
  char host[NI_MAXHOST], port[NI_MAXSERV];
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&addr), length, host, sizeof host, port, sizeof port,
                    NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return "";
  return std::string(host) + ":" + port;
}

std::string port_of(int fd) {
  sockaddr_storage addr{};
  socklen_t length = sizeof addr;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) return "";
  const std::string e = endpoint(addr, length);
  return e.substr(e.rfind(':') + 1);
}

std::string peer_of(int fd) {
  sockaddr_storage addr{};
  socklen_t length = sizeof addr;
  if (::getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) return "";
  return endpoint(addr, length);
}

}  // namespace

bool allowed_host(const std::string& host_header, const std::string& bound_host) {
  const std::string bound = lower(bound_host);
  if (bound == "0.0.0.0" || bound == "::" || bound == "[::]") return true;
  const std::string name = lower(host_name(host_header));
  if (name.empty()) return false;
  if (name == bound || name == "[" + bound + "]") return true;
  return is_loopback(bound) && (name == "localhost" || name == "127.0.0.1" || name == "[::1]");
}

GuardedHttpServer::GuardedHttpServer(std::string bound_host, double header_timeout_s, std::size_t threads)
    : bound_host_(std::move(bound_host)),
      header_timeout_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(header_timeout_s))) {
  new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    set_waiting(req.remote_addr + ":" + std::to_string(req.remote_port), false);
    if (allowed_host(req.get_header_value("Host"), bound_host_)) return HandlerResponse::Unhandled;
    res.status = 403;
    res.set_content("Host \"" + req.get_header_value("Host") + "\" is not this dashboard's address\n", "text/plain");
    return HandlerResponse::Handled;
  });
  // httplib logs a request once its response is written: from then on a keep-alive connection
  // waits for its next header.
  set_logger([this](const httplib::Request& req, const httplib::Response&) {
    set_waiting(req.remote_addr + ":" + std::to_string(req.remote_port), true);
  });
  watchdog_ = std::thread([this] { watch(); });
}

GuardedHttpServer::~GuardedHttpServer() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  watchdog_.join();
}

void GuardedHttpServer::set_waiting(const std::string& peer, bool waiting) {
  std::lock_guard lock(mutex_);
  waiting_since_[peer] = waiting ? Clock::now() : Clock::time_point::max();
}

void GuardedHttpServer::watch() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return stopping_; })) {
    const std::string port = is_valid() && svr_sock_ != INVALID_SOCKET ? port_of(svr_sock_) : "";
    if (port.empty()) continue;
    const auto now = Clock::now();
    std::set<std::string> open;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
      const int fd = std::atoi(entry.path().filename().c_str());
      if (fd == svr_sock_ || port_of(fd) != port) continue;
      const std::string peer = peer_of(fd);  // "" for the listening socket and non-sockets
      if (peer.empty()) continue;
      open.insert(peer);
      const auto since = waiting_since_.try_emplace(peer, now).first;  // new: waits since accept
      if (since->second != Clock::time_point::max() && now - since->second >= header_timeout_) {
        ::shutdown(fd, SHUT_RDWR);  // the blocked read returns; httplib closes the socket
        since->second = Clock::time_point::max();
      }
    }
    std::erase_if(waiting_since_, [&](const auto& kv) { return !open.count(kv.first); });
  }
}

}  // namespace podium::web_dashboard
