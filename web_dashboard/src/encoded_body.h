#pragma once
// Response bodies compressed once, not per request: a body is gzip-compressed once (zlib) when it
// is made (static files at startup, JSON with its cache entry) and sent as it is. (cpp-httplib,
// the server before this one, compressed every response with brotli at quality 11: 25 s for
// three.core.js on a busy 2-core machine.)
#include <memory>
#include <string>

#include "http_server.h"

namespace podium::web_dashboard {

struct EncodedBody {
  std::string plain;
  std::string gzip;  ///< empty when compression would not pay (small bodies)

  /// Compresses `text` once (zlib level 6) unless it is under 1 kB.
  static std::shared_ptr<const EncodedBody> make(std::string text);
};

/// Sends `body` as `mime`, gzip-encoded when the request accepts gzip, a gzip form exists and no
/// byte range is asked for (ranges are of the plain body).
void send_body(const Request& req, Response& res, const std::shared_ptr<const EncodedBody>& body, const std::string& mime);

}  // namespace podium::web_dashboard
