#include "slow_clients.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <memory>
#include <thread>

namespace podium::web_dashboard::testing {

namespace {

using Clock = std::chrono::steady_clock;

// One connection trickling a request header that never ends.
class Trickle {
 public:
  explicit Trickle(int port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    open_ = fd_ >= 0 && ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~Trickle() {
    if (fd_ >= 0) ::close(fd_);
  }
  Trickle(const Trickle&) = delete;
  Trickle& operator=(const Trickle&) = delete;

  /// Sends the next byte of "GET /api/version HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: aaaa...".
  /// False once the server has closed the connection.
  bool send_byte() {
    if (!open_) return false;
    char c;
    const ssize_t n = ::recv(fd_, &c, 1, MSG_DONTWAIT);
    if (n >= 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) return open_ = false;  // a response or a close
    static const std::string start = "GET /api/version HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
    const char next = sent_ < start.size() ? start[sent_] : 'a';
    open_ = ::send(fd_, &next, 1, MSG_NOSIGNAL) == 1;
    ++sent_;
    return open_;
  }

 private:
  int fd_;
  bool open_ = false;
  std::size_t sent_ = 0;
};

}  // namespace

SlowClientRun run_slow_clients(int port, const SlowClientLoad& load) {
  SlowClientRun run;
  std::vector<std::unique_ptr<Trickle>> slow;
  for (int i = 0; i < load.slow_connections; ++i) slow.push_back(std::make_unique<Trickle>(port));
  run.slow_opened = load.slow_connections;
  std::atomic<bool> stop = false;
  // The load itself is paced: one byte per connection per interval.
  std::thread trickle([&] {
    const auto interval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(load.byte_interval_s));
    for (auto next = Clock::now(); !stop; next += interval) {
      for (auto& c : slow) {
        if (c->send_byte()) continue;
        ++run.slow_refused;
        c = std::make_unique<Trickle>(port);  // a real attacker comes back
        ++run.slow_opened;
        c->send_byte();
      }
      while (!stop && Clock::now() < next + interval) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  const auto settle_until =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(load.settle_s));
  while (Clock::now() < settle_until) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto timeout =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::duration<double>(load.request_timeout_s));
  for (int i = 0; i < load.requests; ++i) {
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(timeout);
    client.set_read_timeout(timeout);
    const auto start = Clock::now();
    const auto r = client.Get(load.path.c_str());
    run.latencies_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    run.answered += r && r->status == 200;
  }
  stop = true;
  trickle.join();
  for (auto& c : slow) run.slow_refused += !c->send_byte();  // closed since the last round
  return run;
}

}  // namespace podium::web_dashboard::testing
