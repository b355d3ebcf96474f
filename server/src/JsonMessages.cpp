// The HTTP front end's JSON bodies (JsonMessages.h); in vastray_server_requests, beside the
// checks fuzz/fuzz_http_json.cpp runs on what parses.
#include "JsonMessages.h"

#include <google/protobuf/util/json_util.h>

namespace vastray::server {

std::string toJson(const google::protobuf::Message& message) {
    google::protobuf::util::JsonPrintOptions options;
    options.always_print_primitive_fields = true;
    options.preserve_proto_field_names = true;
    std::string json;
    (void)google::protobuf::util::MessageToJsonString(message, &json, options);
    return json;
}

ServiceStatus fromJson(const std::string& body, google::protobuf::Message* message) {
    if (body.empty()) return {};
    if (body.size() > kMaxJsonBodyBytes) return invalidArgument("body", "larger than 1 MiB");
    google::protobuf::util::JsonParseOptions options;  // unknown fields are errors
    auto status = google::protobuf::util::JsonStringToMessage(body, message, options);
    if (!status.ok()) return invalidArgument("body", std::string(status.message()));
    return {};
}

}  // namespace vastray::server
