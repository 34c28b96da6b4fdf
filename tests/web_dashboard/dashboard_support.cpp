#include "dashboard_support.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <stdexcept>

#include "campaign_spec.h"

namespace podium::web_dashboard::testing {

int raw_status(int port, const std::string& request_line, const std::string& host) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    throw std::runtime_error("cannot connect to port " + std::to_string(port));
  }
  const std::string request = request_line + "\r\nHost: " + host + "\r\nConnection: close\r\n\r\n";
  if (::send(fd, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
    ::close(fd);
    throw std::runtime_error("send failed");
  }
  std::string response;
  char buffer[4096];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) response.append(buffer, static_cast<std::size_t>(n));
  ::close(fd);
  // "HTTP/1.1 404 Not Found"
  if (response.size() < 12) throw std::runtime_error("no HTTP response to " + request_line);
  return std::stoi(response.substr(9, 3));
}

std::string url_encode(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

std::int64_t run_campaign(const std::filesystem::path& dir, const Json& spec, int exit_code) {
  const std::string id = podium::testing::submit_spec(dir, spec);
  const auto run = podium::testing::run_podium({"run", "--workers", "2"}, dir);
  if (run.exit_code != exit_code)
    throw std::runtime_error("podium run exited " + std::to_string(run.exit_code) + ", not " + std::to_string(exit_code) + ": " +
                             run.err);
  return std::stoll(id);
}

Json landscape_spec(const std::string& name, int trials, const Json& extra_config) {
  Json config = {{"artifact", true}};
  config.update(extra_config);
  return podium::testing::stage_spec({.name = name, .seed = 7, .config = config, .trials = trials});
}

Json replay_fixture_spec(const std::string& name, int trials) {
  return podium::testing::stage_spec({.name = name,
                                      .seed = 3,
                                      .retries = 0,
                                      .task = "web_replay_fixture",
                                      .stage = "swing",
                                      .config = nullptr,
                                      .trials = trials});
}

}  // namespace podium::web_dashboard::testing
