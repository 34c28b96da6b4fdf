#pragma once
// Every learner config reads and writes alike: PODIUM_CONFIG_JSON defines Config::to_json and
// Config::from_json from an X-macro list of the config's fields. from_json starts from the
// defaults and reads each field through base::ConfigReader by its type (errors name `where`,
// the field, the value and the rule; unknown fields are rejected).
#include "podium/base/config.h"
#include "podium/base/json.h"

#define PODIUM_CONFIG_JSON(Config, FIELDS, where)    \
  base::Json Config::to_json() const {               \
    base::Json j;                                    \
    FIELDS(PODIUM_CONFIG_WRITE_FIELD)                \
    return j;                                        \
  }                                                  \
  Config Config::from_json(const base::Json& json) { \
    Config c;                                        \
    base::ConfigReader r(json, "", where);           \
    FIELDS(PODIUM_CONFIG_READ_FIELD)                 \
    r.finish();                                      \
    return c;                                        \
  }
#define PODIUM_CONFIG_WRITE_FIELD(f) j[#f] = f;
#define PODIUM_CONFIG_READ_FIELD(f) r.field(#f, c.f);
