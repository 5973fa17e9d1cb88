// tools/cli/validators.h — bounds of the numeric options as CLI11 checks whose refusals read
// as a person would write them: "--jpeg-quality: 0 is out of range (must be 1..100)",
// "--lenticular-pitch: 1e30 is out of range (must be > 0 and at most 10000)". CLI11's own
// Range()/PositiveNumber print their bounds with %f (the largest double in ~310 digits).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace mvr::cli {

/// A bound as text: whole numbers up to 1e7 in full ("8192"), others as %g ("1e+06").
std::string readableNumber(double v);

/// A number in lo..hi (both included).
CLI::Validator numberIn(double lo, double hi);
/// A number > 0 and at most hi.
CLI::Validator positiveAtMost(double hi);
/// A whole number in lo..hi (both included).
CLI::Validator wholeIn(long lo, long hi);
/// A non-zero number whose magnitude is in lo..hi.
CLI::Validator nonZeroMagnitudeIn(double lo, double hi);
/// Not the empty string: `what` says what was expected ("a display name; `mvr info --displays`").
CLI::Validator nonEmpty(const std::string& what);

}  // namespace mvr::cli
