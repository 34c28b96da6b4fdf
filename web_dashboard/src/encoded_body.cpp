#include "encoded_body.h"

#include <zlib.h>

#include <stdexcept>

namespace podium::web_dashboard {

namespace {

std::string gzip_of(const std::string& text) {
  z_stream z{};
  // windowBits 15 + 16: a gzip header and trailer, as Content-Encoding: gzip needs.
  if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib: deflateInit2 failed");
  std::string out(deflateBound(&z, static_cast<uLong>(text.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int status = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (status != Z_STREAM_END) throw std::runtime_error("zlib: deflate did not finish");
  return out;
}

bool accepts_gzip(const Request& req) { return req.accept_encoding.find("gzip") != std::string::npos; }

}  // namespace

std::shared_ptr<const EncodedBody> EncodedBody::make(std::string text) {
  auto body = std::make_shared<EncodedBody>();
  if (text.size() >= 1024) body->gzip = gzip_of(text);
  body->plain = std::move(text);
  return body;
}

void send_body(const Request& req, Response& res, const std::shared_ptr<const EncodedBody>& body, const std::string& mime) {
  const bool gzip = !body->gzip.empty() && !req.has_range && accepts_gzip(req);
  if (!body->gzip.empty()) res.set_header("Vary", "Accept-Encoding");
  if (gzip) res.set_header("Content-Encoding", "gzip");
  res.ranges = !gzip;
  res.text = std::shared_ptr<const std::string>(body, gzip ? &body->gzip : &body->plain);  // shares the body, no copy
  res.content_type = mime;
}

}  // namespace podium::web_dashboard
