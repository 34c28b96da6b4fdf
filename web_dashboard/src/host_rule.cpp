#include "host_rule.h"

#include <algorithm>
#include <cctype>

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

bool is_loopback(const std::string& host) { return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0; }

}  // namespace

bool allowed_host(const std::string& host_header, const std::string& bound_host) {
  const std::string bound = lower(bound_host);
  if (bound == "0.0.0.0" || bound == "::" || bound == "[::]") return true;
  const std::string name = lower(host_name(host_header));
  if (name.empty()) return false;
  if (name == bound || name == "[" + bound + "]") return true;
  return is_loopback(bound) && (name == "localhost" || name == "127.0.0.1" || name == "[::1]");
}

}  // namespace podium::web_dashboard
