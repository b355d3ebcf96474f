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

const char* statusCodeNameOfHttp(int httpStatus) {
    if (httpStatus >= 200 && httpStatus < 300) return "OK";
    switch (httpStatus) {
        case 400:
        case 411:
        case 415:
            return "INVALID_ARGUMENT";
        case 401:
            return "UNAUTHENTICATED";
        case 404:
            return "NOT_FOUND";
        case 409:
            return "FAILED_PRECONDITION";
        case 413:
        case 429:
            return "RESOURCE_EXHAUSTED";
        case 416:
            return "OUT_OF_RANGE";
        case 499:
            return "CANCELLED";
        case 500:
            return "INTERNAL";
        case 503:
            return "UNAVAILABLE";
    }
    return "UNKNOWN";
}

}  // namespace vastray::server
