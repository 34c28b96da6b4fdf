#pragma once
// Response bodies compressed once, not per request. httplib compresses every in-memory body it
// sends, and Debian's build picks brotli at quality 11 for browsers: three.core.js (1.4 MB) took
// 25 s per request on a busy 2-core machine, and pages timed out while their scripts loaded. A
// body here is gzip-compressed once (zlib) and sent through a sized content provider, which
// httplib sends as it is.
#include <cstdint>
#include <memory>
#include <string>

#include <httplib.h>

namespace podium::web_dashboard {

struct EncodedBody {
  std::string plain;
  std::string gzip;  ///< empty when compression would not pay (small bodies)

  /// Compresses `text` once (zlib level 6) unless it is under 1 kB.
  static std::shared_ptr<const EncodedBody> make(std::string text);
};

/// True if every requested byte range starts inside `size` bytes (RFC 9110 §14.1.2; httplib checks
/// this for in-memory bodies but not for streamed ones).
bool satisfiable(const httplib::Ranges& ranges, std::uintmax_t size);

/// Sends `body` as `mime`, gzip-encoded when the request accepts gzip, a gzip form exists and no
/// byte range is asked for (ranges are of the plain body; 416 when unsatisfiable).
void send_body(const httplib::Request& req, httplib::Response& res, std::shared_ptr<const EncodedBody> body,
               const std::string& mime);

}  // namespace podium::web_dashboard
