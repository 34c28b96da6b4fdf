#pragma once
// The dashboard's HTTP server: cpp-httplib's, with two guards its options do not give.
// - Header deadline (slow clients): a connection that has not sent a whole request header within
//   header_timeout_s of starting to wait for it (accept, or its previous response sent) is shut
//   down. httplib's read timeout is per recv(), so a client sending one byte a second would hold
//   a worker thread for ever. httplib hands its handlers no socket, so a watchdog thread finds
//   the server's connections among the process's descriptors (by local port) and tells them
//   apart by peer address, which the handlers do see.
// - Host rule (DNS rebinding): a request whose Host header is not a name of the bound address is
//   refused with 403; see allowed_host().
#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace podium::web_dashboard {

/// True if `host_header` ("name" or "name:port") may reach a server bound to `bound_host`:
/// any value when bound to a wildcard address (0.0.0.0, ::), else the bound address itself,
/// and for a loopback address also localhost, 127.0.0.1 and [::1]. The port is not compared
/// (the name alone decides whose site a page belongs to).
bool allowed_host(const std::string& host_header, const std::string& bound_host);

class GuardedHttpServer : public httplib::Server {
 public:
  /// `threads`: the worker pool (slow clients hold one each until the deadline).
  GuardedHttpServer(std::string bound_host, double header_timeout_s, std::size_t threads);
  ~GuardedHttpServer() override;

 private:
  using Clock = std::chrono::steady_clock;
  void watch();
  // The connection from `peer` ("address:port") waits for a header from now on, or is busy.
  void set_waiting(const std::string& peer, bool waiting);

  std::string bound_host_;
  Clock::duration header_timeout_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<std::string, Clock::time_point> waiting_since_;  // by peer; max() while busy
  std::thread watchdog_;
};

}  // namespace podium::web_dashboard
