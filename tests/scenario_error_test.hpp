#pragma once
/// \file
/// One check for the scenario reader's errors: a text read as a scenario file must throw a
/// ScenarioError at a given line that names a given key and says a given thing.

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "io/scenario.hpp"

namespace cleave::testing {

/// Parses `text` as the file `source` and checks that it throws a ScenarioError whose file
/// is `source`, whose line is `line` (and column `column`, unless 0) and whose key is `key`;
/// its what() must start "SOURCE:LINE:" (then "COLUMN:"), read "key 'KEY': " (unless the key
/// is empty) and hold `part`. Returns what() ("" when nothing was thrown) for more checks.
inline std::string expect_scenario_error(std::string_view text, const std::string& source, int line,
                                         const std::string& key, const std::string& part,
                                         int column = 0) {
  try {
    (void)io::parse_scenario(text, source);
  } catch (const io::ScenarioError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), source) << what;
    EXPECT_EQ(e.line(), line) << what;
    if (column != 0) {
      EXPECT_EQ(e.column(), column) << what;
    }
    EXPECT_EQ(e.key(), key) << what;
    const std::string at = source + ":" + std::to_string(line) + ":" +
                           (column != 0 ? std::to_string(column) + ":" : std::string());
    EXPECT_EQ(what.rfind(at, 0), 0u) << what << "\n  does not start with: " << at;
    if (!key.empty()) {
      EXPECT_NE(what.find("key '" + key + "': "), std::string::npos) << what;
    }
    EXPECT_NE(what.find(part), std::string::npos) << what << "\n  lacks: " << part;
    return what;
  }
  ADD_FAILURE() << "no ScenarioError for:\n" << text;
  return {};
}

}  // namespace cleave::testing

/// expect_scenario_error(text, source, line, key, part[, column]), traced to the line that
/// uses it.
#define EXPECT_SCENARIO_ERROR_IN(source, text, line, key, ...)                            \
  do {                                                                                    \
    SCOPED_TRACE(key);                                                                    \
    (void)::cleave::testing::expect_scenario_error(text, source, line, key, __VA_ARGS__); \
  } while (false)

/// The same for a text read as "mem.toml".
#define EXPECT_SCENARIO_ERROR(text, line, key, part) \
  EXPECT_SCENARIO_ERROR_IN("mem.toml", text, line, key, part)
