#pragma once
// The outcome of a service call, with the canonical code that both front ends map at their
// boundary (gRPC status code; HTTP status). Domain code returns these, never throws.
#include <cassert>
#include <optional>
#include <string>
#include <utility>

namespace vastray::server {

// Same meanings (and numbering) as the gRPC canonical codes.
enum class StatusCode {
    Ok = 0,
    Cancelled = 1,
    InvalidArgument = 3,
    NotFound = 5,
    AlreadyExists = 6,
    ResourceExhausted = 8,
    FailedPrecondition = 9,
    Internal = 13,
    Unavailable = 14,
    Unauthenticated = 16,
};

const char* statusCodeName(StatusCode code);  // "INVALID_ARGUMENT", ...
int httpStatusOf(StatusCode code);            // 400, 404, 409, 429, ...
// The canonical code name of an HTTP response status, for one label scheme in the request
// metrics of both front ends: the inverse of httpStatusOf (409 is FAILED_PRECONDITION), and
// for statuses only HTTP has: 2xx OK, 411 and 415 INVALID_ARGUMENT, 413 RESOURCE_EXHAUSTED,
// 416 OUT_OF_RANGE; any other status UNKNOWN.
const char* statusCodeNameOfHttp(int httpStatus);

class ServiceStatus {
public:
    ServiceStatus() = default;
    ServiceStatus(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
    static ServiceStatus ok() { return {}; }

    bool isOk() const { return code_ == StatusCode::Ok; }
    explicit operator bool() const { return isOk(); }
    StatusCode code() const { return code_; }
    const std::string& message() const { return message_; }

private:
    StatusCode code_ = StatusCode::Ok;
    std::string message_;
};

inline ServiceStatus invalidArgument(const std::string& field, const std::string& why) {
    return {StatusCode::InvalidArgument, field + ": " + why};
}
inline ServiceStatus notFound(std::string message) { return {StatusCode::NotFound, std::move(message)}; }
inline ServiceStatus internalError(std::string message) { return {StatusCode::Internal, std::move(message)}; }

template <typename T>
class ServiceResult {
public:
    ServiceResult(T value) : value_(std::move(value)) {}
    ServiceResult(ServiceStatus status) : status_(std::move(status)) { assert(!status_.isOk()); }

    bool isOk() const { return value_.has_value(); }
    explicit operator bool() const { return isOk(); }
    const ServiceStatus& status() const { return status_; }
    T& operator*() {
        assert(value_);
        return *value_;
    }
    const T& operator*() const {
        assert(value_);
        return *value_;
    }
    T* operator->() { return &**this; }
    const T* operator->() const { return &**this; }

private:
    std::optional<T> value_;
    ServiceStatus status_;
};

}  // namespace vastray::server
