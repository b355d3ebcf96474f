#include "vastray/server/ServiceStatus.h"

namespace vastray::server {

const char* statusCodeName(StatusCode code) {
    switch (code) {
        case StatusCode::Ok:
            return "OK";
        case StatusCode::Cancelled:
            return "CANCELLED";
        case StatusCode::InvalidArgument:
            return "INVALID_ARGUMENT";
        case StatusCode::NotFound:
            return "NOT_FOUND";
        case StatusCode::AlreadyExists:
            return "ALREADY_EXISTS";
        case StatusCode::ResourceExhausted:
            return "RESOURCE_EXHAUSTED";
        case StatusCode::FailedPrecondition:
            return "FAILED_PRECONDITION";
        case StatusCode::Internal:
            return "INTERNAL";
        case StatusCode::Unavailable:
            return "UNAVAILABLE";
        case StatusCode::Unauthenticated:
            return "UNAUTHENTICATED";
    }
    return "UNKNOWN";
}

int httpStatusOf(StatusCode code) {
    switch (code) {
        case StatusCode::Ok:
            return 200;
        case StatusCode::Cancelled:
            return 499;
        case StatusCode::InvalidArgument:
            return 400;
        case StatusCode::NotFound:
            return 404;
        case StatusCode::AlreadyExists:
            return 409;
        case StatusCode::ResourceExhausted:
            return 429;
        case StatusCode::FailedPrecondition:
            return 409;
        case StatusCode::Internal:
            return 500;
        case StatusCode::Unavailable:
            return 503;
        case StatusCode::Unauthenticated:
            return 401;
    }
    return 500;
}

}  // namespace vastray::server
