#pragma once
// Bookkeeping of asked-but-not-told ids shared by every algorithm: tell() must reject ids that
// were never asked or were already told (the conformance suite checks the message).
#include <cstdint>
#include <set>
#include <string>

#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::search {

inline void take_pending(std::set<std::uint64_t>& pending, std::uint64_t id, const std::string& algorithm) {
  if (pending.erase(id) == 0)
    throw base::UserError(algorithm + ": tell() got id " + std::to_string(id) +
                          ", which is not a pending proposal (never asked or already told)");
}

inline base::Json pending_to_json(const std::set<std::uint64_t>& pending) {
  return base::Json(std::vector<std::uint64_t>(pending.begin(), pending.end()));
}

inline std::set<std::uint64_t> pending_from_json(const base::Json& j) {
  const auto ids = j.get<std::vector<std::uint64_t>>();
  return {ids.begin(), ids.end()};
}

}  // namespace podium::search
