// Table-driven scenario checks: a scenario text and the verdict parse_scenario then validate_scenario
// give it ("" for none). A verdict ending in a space is a prefix of the message.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <optional>
#include <string>

#include "core/scenario/run_builder.hpp"

namespace kessler::test {

struct VerdictCase {
  const char* name;
  std::string text;
  const char* expected;
};

inline void expect_verdict(const VerdictCase& c) {
  v1::Scenario scenario;
  std::optional<FieldError> error = parse_scenario(c.text, scenario);
  if (!error) error = validate_scenario(scenario);
  const std::string message = error ? error->message() : "";
  const std::string expected = c.expected;
  if (!expected.empty() && expected.back() == ' ')
    EXPECT_EQ(message.rfind(expected, 0), 0u) << message << "\n" << c.text;
  else
    EXPECT_EQ(message, expected) << c.text;
}

// The case's name as a test name: letters and digits, the rest '_'.
struct VerdictCaseName {
  template <typename Info>
  std::string operator()(const Info& info) const {
    std::string name = info.param.name;
    for (auto& ch : name)
      if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
  }
};

}  // namespace kessler::test
