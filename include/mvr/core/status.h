// mvr/core/status.h — Status and Result<T>: how mvr reports errors from external input.
//
// External input (files, command-line values, sizes, view counts) never aborts: functions
// return a Status or a Result<T> whose message names the function, the value and what was
// expected, e.g. "mvr::loadMesh(): bunny.obj: file not found". Internal invariants use
// MVR_ASSERT (debug builds only). We keep our own small type because std::expected is C++23.
#pragma once

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#define MVR_ASSERT(cond) assert(cond)

namespace mvr {

/// Error categories; the CLI maps them to exit codes (see exitCode()).
enum class ErrorCode {
    Ok = 0,
    Usage,        ///< a parameter is out of range or nonsensical (exit 1)
    Input,        ///< a file is missing, unreadable or malformed (exit 2)
    Unsupported,  ///< not available in this build or on this driver (exit 3)
    Output,       ///< an output file could not be written (exit 4)
    Internal,     ///< a driver or library failed unexpectedly (exit 5)
};

/// CLI exit code of an error category: 0 ok, 1 usage, 2 input, 3 unsupported, 4 output, 5 internal.
inline int exitCode(ErrorCode code) { return static_cast<int>(code); }

class [[nodiscard]] Status {
public:
    Status() = default;
    Status(ErrorCode code, std::string message) : mCode(code), mMessage(std::move(message)) {}

    static Status ok() { return {}; }
    bool isOk() const { return mCode == ErrorCode::Ok; }
    explicit operator bool() const { return isOk(); }
    ErrorCode code() const { return mCode; }
    const std::string& message() const { return mMessage; }

private:
    ErrorCode mCode = ErrorCode::Ok;
    std::string mMessage;
};

inline Status usageError(std::string m) { return {ErrorCode::Usage, std::move(m)}; }
inline Status inputError(std::string m) { return {ErrorCode::Input, std::move(m)}; }
inline Status unsupportedError(std::string m) { return {ErrorCode::Unsupported, std::move(m)}; }
inline Status outputError(std::string m) { return {ErrorCode::Output, std::move(m)}; }
inline Status internalError(std::string m) { return {ErrorCode::Internal, std::move(m)}; }

/// A value or the Status that explains why there is none.
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : mData(std::move(value)) {}
    Result(Status status) : mData(std::move(status)) {
        MVR_ASSERT(!std::get<Status>(mData).isOk());
    }

    bool isOk() const { return std::holds_alternative<T>(mData); }
    explicit operator bool() const { return isOk(); }
    const Status& status() const {
        static const Status kOk;
        return isOk() ? kOk : std::get<Status>(mData);
    }
    T& value() & { return std::get<T>(mData); }
    const T& value() const& { return std::get<T>(mData); }
    T&& value() && { return std::get<T>(std::move(mData)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

private:
    std::variant<T, Status> mData;
};

}  // namespace mvr
