#pragma once
// The Host rule (DNS rebinding): a request whose Host header is not a name of the bound address
// is refused with 403. A page of evil.example that resolves its name to 127.0.0.1 sends
// "Host: evil.example", so it cannot read the dashboard through the victim's browser.
#include <string>

namespace podium::web_dashboard {

/// True if `host_header` ("name" or "name:port") may reach a server bound to `bound_host`:
/// any value when bound to a wildcard address (0.0.0.0, ::), else the bound address itself,
/// and for a loopback address also localhost, 127.0.0.1 and [::1]. The port is not compared
/// (the name alone decides whose site a page belongs to).
bool allowed_host(const std::string& host_header, const std::string& bound_host);

}  // namespace podium::web_dashboard
