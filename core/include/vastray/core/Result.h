#pragma once
// One error type for the whole project: data and user errors are values, never exceptions.
#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace vastray {

class Status {
public:
    Status() = default;
    static Status ok() { return Status(); }
    static Status error(std::string message) { return Status(std::move(message), true); }

    bool isOk() const { return !failed_; }
    explicit operator bool() const { return isOk(); }
    const std::string& message() const { return message_; }
    const Status& status() const { return *this; }  // lets VASTRAY_TRY take a Status or a Result

    // Prefixes context ("bunny.ply: ") to an error; a no-op on success.
    Status withContext(const std::string& prefix) const {
        return failed_ ? Status(prefix + message_, true) : *this;
    }

private:
    Status(std::string message, bool failed) : message_(std::move(message)), failed_(failed) {}
    std::string message_;
    bool failed_ = false;
};

template <typename T>
class Result {
public:
    Result(T value) : value_(std::move(value)) {}
    Result(Status status) : status_(std::move(status)) { assert(!status_.isOk()); }

    bool isOk() const { return value_.has_value(); }
    explicit operator bool() const { return isOk(); }
    const Status& status() const { return status_; }
    const std::string& message() const { return status_.message(); }

    T& value() & { assert(value_); return *value_; }
    const T& value() const& { assert(value_); return *value_; }
    T&& value() && { assert(value_); return std::move(*value_); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

private:
    std::optional<T> value_;
    Status status_;
};

}  // namespace vastray

// Returns early from a function returning Status or Result<T> when `expr` failed.
#define VASTRAY_TRY(expr)                                          \
    do {                                                           \
        auto vastray_status_ = (expr);                             \
        if (!vastray_status_.isOk()) return vastray_status_.status(); \
    } while (0)
