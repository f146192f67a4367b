#pragma once

// Options several commands share, and the checks that keep their messages short and their values
// exact: a number must be finite and in its range, a seed must fit 64 bits (CLI11 would clamp it),
// and a value is quoted only up to a length in a message.

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace emrm::cli {

/// `text` as a message quotes it: at most `limit` characters, then "…".
inline std::string shortened(std::string_view text, std::size_t limit = 40) {
  return text.size() <= limit ? std::string(text) : std::string(text.substr(0, limit)) + "…";
}

/// A finite number in [low, high] (CLI11's Range lets NaN through and prints its bounds in full).
inline CLI::Validator finite_in(double low, double high) {
  return CLI::Validator(
      [low, high](std::string& value) -> std::string {
        double x = 0.0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
        if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(x) || x < low || x > high)
          return fmt::format("expected a number in [{:g}, {:g}], got '{}'", low, high, shortened(value));
        return {};
      },
      fmt::format("in [{:g}, {:g}]", low, high));
}

/// A whole number in [0, 2^64 − 1], written in decimal digits.
inline CLI::Validator seed_value() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        std::uint64_t x = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
        if (ec != std::errc() || end != value.data() + value.size())
          return fmt::format("expected a whole number from 0 to 18446744073709551615, got '{}'", shortened(value));
        return {};
      },
      "UINT64");
}

/// --threads N: 0 (every core) to 1024.
inline CLI::Option* add_threads_option(CLI::App* command, int& threads, const std::string& description) {
  return command->add_option("--threads", threads, description)->check(CLI::Range(0, 1024, "0 to 1024"));
}

}  // namespace emrm::cli
