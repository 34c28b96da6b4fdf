#include "podium/learn/env.h"

#include "podium/base/error.h"

namespace podium::learn {

void Env::load_state(const base::Json&) {
  throw base::UserError("learn: this environment does not support load_state (its save_state returns nullopt)");
}

}  // namespace podium::learn
