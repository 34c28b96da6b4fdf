#pragma once
// Slow clients against a dashboard: connections that each send a request header one byte at a
// time (reconnecting whenever the server closes them), while ordinary GETs are made one after
// another, each on a fresh connection. Shared by the security test (every ordinary request is
// answered) and bench/web_dashboard's slow-client bench (their latencies).
#include <string>
#include <vector>

namespace podium::web_dashboard::testing {

struct SlowClientLoad {
  int slow_connections = 64;
  double byte_interval_s = 1.0;  ///< each slow connection sends one header byte this often
  int requests = 20;             ///< ordinary GETs, one after another
  std::string path = "/api/campaigns";
  double settle_s = 2.0;  ///< the slow connections trickle this long before the first GET
  double request_timeout_s = 20.0;
};

struct SlowClientRun {
  int answered = 0;                  ///< ordinary GETs answered 200
  std::vector<double> latencies_ms;  ///< per ordinary GET (answered or not), in order
  int slow_opened = 0;               ///< slow connections opened (first ones and reconnections)
  int slow_refused = 0;              ///< slow connections the server closed or refused
};

SlowClientRun run_slow_clients(int port, const SlowClientLoad& load);

}  // namespace podium::web_dashboard::testing
