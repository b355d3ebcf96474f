#pragma once
// The HTTP front end's JSON bodies: proto messages from and to JSON, with the .proto's field
// names; unknown fields are errors. fuzz/fuzz_http_json.cpp feeds fromJson garbage.
#include <google/protobuf/message.h>

#include <cstddef>
#include <string>

#include "vastray/server/ServiceStatus.h"

namespace vastray::server {

constexpr size_t kMaxJsonBodyBytes = 1u << 20;  // larger JSON bodies are refused unread

std::string toJson(const google::protobuf::Message& message);
// OK for an empty body (the message stays empty); INVALID_ARGUMENT naming `body` otherwise.
ServiceStatus fromJson(const std::string& body, google::protobuf::Message* message);

}  // namespace vastray::server
