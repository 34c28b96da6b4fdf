#pragma once
/// Errors in three tiers (docs/style.md "Errors everywhere"):
///  - PODIUM_DEBUG_ASSERT: programmer errors, checked in debug builds only;
///  - PODIUM_CHECK: invariants that must hold in every build; aborts with file, line and condition;
///  - podium::base::UserError: bad user input (spec, model file, CLI); thrown, caught at the CLI,
///    printed as one line. Its message says where, what, the value and the rule.
/// Expected failures (a diverged trial, a crashed plugin) are return values, not exceptions.
#include <stdexcept>
#include <string>

namespace podium::base {

/// Thrown for invalid user input. The CLI prints what() as one line and exits 2.
class UserError : public std::runtime_error {
 public:
  explicit UserError(const std::string& message) : std::runtime_error(message) {}
};

/// Thrown when the environment fails (I/O, database, missing plugin). The CLI exits 1.
class RuntimeError : public std::runtime_error {
 public:
  explicit RuntimeError(const std::string& message) : std::runtime_error(message) {}
};

[[noreturn]] void check_failed(const char* condition, const char* file, int line, const std::string& detail);

}  // namespace podium::base

#define PODIUM_CHECK(cond, detail)                                                \
  do {                                                                            \
    if (!(cond)) ::podium::base::check_failed(#cond, __FILE__, __LINE__, detail); \
  } while (0)

#ifdef NDEBUG
#define PODIUM_DEBUG_ASSERT(cond) ((void)0)
#else
#define PODIUM_DEBUG_ASSERT(cond) PODIUM_CHECK(cond, "debug assertion")
#endif
