#pragma once
// The comments of the vastray.v1 .proto files, which the generated C++ descriptors lack: read
// from a descriptor set compiled with --include_source_info and embedded in the binary
// (server/CMakeLists.txt).
#include <map>
#include <string>

namespace vastray::server {

// Leading comment (else trailing comment) of each service, method, message, field, enum and
// enum value, keyed by its full name ("vastray.v1.Job.state", "vastray.v1.RenderService.GetJob");
// comment lines are trimmed and joined with spaces. Elements without a comment are absent.
const std::map<std::string, std::string>& protoComments();

// The comment of `fullName`, or "" when it has none.
std::string protoComment(const std::string& fullName);

// Each vastray.v1 .proto file, by its name ("vastray/v1/render_service.proto"), as a serialized
// FileDescriptorProto with its source_code_info (the comments): what server reflection sends.
const std::map<std::string, std::string>& commentedProtoFiles();

}  // namespace vastray::server
