#pragma once
// `podium submit SPEC --set PATH=VALUE`: a variant of a shipped spec (another seed, more steps, a
// stage's config key) in one command, with the edited spec the one validated and stored, so the
// database says what ran.
#include <string>

#include "podium/base/json.h"

namespace podium::orchestrator {

/// Applies one edit "PATH=VALUE" to `spec`. PATH is written as podium's errors name JSON paths
/// (`seed`, `stages[0].config.total_steps`); VALUE is JSON (`3`, `[64,64]`, `"x"`), or a string
/// when it does not parse as JSON (`name=getup-b`). Object members missing on the way are created
/// (validation then names any key a task does not know); an array item must exist. Throws
/// base::UserError naming the edit and what is wrong with it.
void apply_spec_edit(base::Json& spec, const std::string& edit);

}  // namespace podium::orchestrator
