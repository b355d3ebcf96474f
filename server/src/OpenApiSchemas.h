#pragma once
// The components/schemas of /openapi.json: one JSON Schema (2020-12, as OpenAPI 3.1 takes it)
// per message and enum of the vastray.v1 protos in their proto3 JSON mapping, generated from
// the descriptors at run time so they cannot drift from the contract, described by the proto
// comments (ProtoComments.h).
#include <nlohmann/json.hpp>

#include <string>

namespace vastray::server {

// Name of the schema of a proto message or enum: "vastray.v1.JobEvent.Kind" -> "JobEvent_Kind".
std::string openApiSchemaName(const std::string& protoFullName);
// {"$ref": "#/components/schemas/NAME"}.
nlohmann::json openApiSchemaRef(const std::string& protoFullName);
// Every message and enum of the vastray.v1 files, keyed by openApiSchemaName.
nlohmann::json openApiProtoSchemas();

}  // namespace vastray::server
