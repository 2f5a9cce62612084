#pragma once
// CLI11's Range and PositiveNumber let NaN through (every comparison with NaN is false), and a NaN
// seconds or grams then runs forever or computes nonsense: these checks refuse it by name.
#include <CLI/CLI.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace dynweigh::tools {

// A finite number in [low, high].
inline CLI::Validator FiniteRange(double low, double high) {
  std::ostringstream description;
  description << "FLOAT in [" << low << " - " << high << "]";
  return CLI::Validator(
      [low, high](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value < low || value > high) {
          std::ostringstream why;
          why << "Value " << text << " not a number in range " << low << " to " << high;
          return why.str();
        }
        return {};
      },
      description.str());
}

// Any finite number.
inline CLI::Validator Finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) return "Value " + text + " is not a finite number";
        return {};
      },
      "FLOAT");
}

// A finite number above zero.
inline CLI::Validator PositiveFinite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || !(value > 0.0)) {
          return "Value " + text + " is not a positive finite number";
        }
        return {};
      },
      "FLOAT:POSITIVE");
}

}  // namespace dynweigh::tools
