#include "validators.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>

#include <fmt/core.h>

namespace mvr::cli {

std::string readableNumber(double v) {
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) <= 1e7)
        return fmt::format("{}", static_cast<long long>(v));
    return fmt::format("{:g}", v);
}

namespace {

/// The whole text as a finite number, else nullopt.
std::optional<double> parseNumber(const std::string& text) {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(begin, &end);
    if (end == begin || *end != '\0' || !std::isfinite(v)) return std::nullopt;
    return v;
}

/// A validator of numbers: `ok` says whether a value is in bounds, `bounds` is the rule.
CLI::Validator numberRule(std::function<bool(double)> ok, std::string bounds, std::string name,
                          bool whole = false) {
    return CLI::Validator(
        [ok = std::move(ok), bounds, whole](std::string& text) -> std::string {
            const std::optional<double> v = parseNumber(text);
            if (!v) return fmt::format("'{}' is not a finite number ({})", text, bounds);
            if (whole && *v != std::floor(*v))
                return fmt::format("'{}' is not a whole number ({})", text, bounds);
            if (!ok(*v)) return fmt::format("{} is out of range ({})", text, bounds);
            return {};
        },
        std::move(name));
}

}  // namespace

CLI::Validator numberIn(double lo, double hi) {
    return numberRule([lo, hi](double v) { return v >= lo && v <= hi; },
                      fmt::format("must be {}..{}", readableNumber(lo), readableNumber(hi)),
                      "NUMBER");
}

CLI::Validator positiveAtMost(double hi) {
    return numberRule([hi](double v) { return v > 0.0 && v <= hi; },
                      fmt::format("must be > 0 and at most {}", readableNumber(hi)), "POSITIVE");
}

CLI::Validator wholeIn(long lo, long hi) {
    return numberRule([lo, hi](double v) { return v >= double(lo) && v <= double(hi); },
                      fmt::format("must be a whole number {}..{}", lo, hi), "INT", true);
}

CLI::Validator nonZeroMagnitudeIn(double lo, double hi) {
    return numberRule([lo, hi](double v) { return std::abs(v) >= lo && std::abs(v) <= hi; },
                      fmt::format("must be non-zero, {} <= |value| <= {}", readableNumber(lo),
                                  readableNumber(hi)),
                      "NONZERO");
}

CLI::Validator nonEmpty(const std::string& what) {
    return CLI::Validator(
        [what](std::string& text) -> std::string {
            if (text.find_first_not_of(" \t") == std::string::npos)
                return fmt::format("'{}' is empty (expected {})", text, what);
            return {};
        },
        "");
}

}  // namespace mvr::cli
