#include "OpenApi.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include <nlohmann/json.hpp>

#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

namespace vastray::server {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::EnumDescriptor;
using google::protobuf::FieldDescriptor;
using nlohmann::json;

std::string schemaName(const std::string& fullName) {
    const std::string prefix = "vastray.v1.";
    std::string name = fullName.rfind(prefix, 0) == 0 ? fullName.substr(prefix.size()) : fullName;
    for (char& c : name)
        if (c == '.') c = '_';
    return name;
}

json schemaRef(const std::string& fullName) {
    return {{"$ref", "#/components/schemas/" + schemaName(fullName)}};
}

json enumSchema(const EnumDescriptor* e) {
    json values = json::array();
    for (int i = 0; i < e->value_count(); ++i) values.push_back(e->value(i)->name());
    return {{"type", "string"}, {"enum", values}};
}

// One value of the field, in the proto3 JSON mapping.
json valueSchema(const FieldDescriptor* f) {
    switch (f->type()) {
        case FieldDescriptor::TYPE_STRING:
            return {{"type", "string"}};
        case FieldDescriptor::TYPE_BYTES:
            return {{"type", "string"}, {"format", "byte"}};
        case FieldDescriptor::TYPE_BOOL:
            return {{"type", "boolean"}};
        case FieldDescriptor::TYPE_FLOAT:
        case FieldDescriptor::TYPE_DOUBLE:
            return {{"type", "number"}};
        case FieldDescriptor::TYPE_INT64:
        case FieldDescriptor::TYPE_UINT64:
        case FieldDescriptor::TYPE_SINT64:
        case FieldDescriptor::TYPE_FIXED64:
        case FieldDescriptor::TYPE_SFIXED64:
            return {{"type", "string"}, {"format", "int64"}};
        case FieldDescriptor::TYPE_ENUM:
            return schemaRef(f->enum_type()->full_name());
        case FieldDescriptor::TYPE_MESSAGE:
            if (f->message_type()->full_name() == "google.protobuf.Timestamp")
                return {{"type", "string"}, {"format", "date-time"}};
            return schemaRef(f->message_type()->full_name());
        default:
            return {{"type", "integer"}, {"format", "int32"}};
    }
}

json fieldSchema(const FieldDescriptor* f) {
    if (f->is_map())
        return {{"type", "object"}, {"additionalProperties", valueSchema(f->message_type()->map_value())}};
    if (f->is_repeated()) return {{"type", "array"}, {"items", valueSchema(f)}};
    return valueSchema(f);
}

void addMessage(const Descriptor* d, json& schemas) {
    if (d->options().map_entry()) return;
    json properties = json::object();
    for (int i = 0; i < d->field_count(); ++i) properties[d->field(i)->name()] = fieldSchema(d->field(i));
    schemas[schemaName(d->full_name())] = {{"type", "object"}, {"properties", properties}};
    for (int i = 0; i < d->nested_type_count(); ++i) addMessage(d->nested_type(i), schemas);
    for (int i = 0; i < d->enum_type_count(); ++i)
        schemas[schemaName(d->enum_type(i)->full_name())] = enumSchema(d->enum_type(i));
}

json schemasOf(const google::protobuf::FileDescriptor* file, json& schemas) {
    for (int i = 0; i < file->message_type_count(); ++i) addMessage(file->message_type(i), schemas);
    for (int i = 0; i < file->enum_type_count(); ++i)
        schemas[schemaName(file->enum_type(i)->full_name())] = enumSchema(file->enum_type(i));
    return schemas;
}

json response(const char* description, const char* schema) {
    json r = {{"description", description}};
    if (schema)
        r["content"] = {{"application/json", {{"schema", schemaRef(std::string("vastray.v1.") + schema)}}}};
    return r;
}

json body(const char* schema) {
    return {
        {"required", true},
        {"content", {{"application/json", {{"schema", schemaRef(std::string("vastray.v1.") + schema)}}}}}};
}

json paths() {
    json p;
    p["/v1/scenes"]["put"] = {{"summary", "Upload a scene (body: the file; ?name=FILE)"},
                              {"requestBody", {{"content", {{"application/octet-stream", json::object()}}}}},
                              {"responses", {{"200", response("the stored scene", "Scene")}}}};
    p["/v1/scenes"]["get"] = {{"summary", "List scenes (?page_size, ?page_token)"},
                              {"responses", {{"200", response("a page", "ListScenesResponse")}}}};
    p["/v1/scenes:findMissing"]["post"] = {
        {"requestBody", body("FindMissingRequest")},
        {"responses", {{"200", response("unknown digests", "FindMissingResponse")}}}};
    p["/v1/scenes/{id}"]["get"] = {{"responses", {{"200", response("the scene", "Scene")}}}};
    p["/v1/scenes/{id}"]["delete"] = {{"responses", {{"200", response("deleted", "DeleteSceneResponse")}}}};
    p["/v1/jobs"]["post"] = {{"summary", "Submit a job (Idempotency-Key header = request_id)"},
                             {"requestBody", body("SubmitJobRequest")},
                             {"responses",
                              {{"202", response("queued; Location names the job", "Job")},
                               {"200", response("an earlier job with this Idempotency-Key", "Job")}}}};
    p["/v1/jobs"]["get"] = {{"summary", "List jobs (?state, ?page_size, ?page_token)"},
                            {"responses", {{"200", response("a page", "ListJobsResponse")}}}};
    p["/v1/jobs/{id}"]["get"] = {{"responses", {{"200", response("the job", "Job")}}}};
    p["/v1/jobs/{id}:cancel"]["post"] = {{"requestBody", body("CancelJobRequest")},
                                         {"responses", {{"200", response("the cancelled job", "Job")}}}};
    p["/v1/jobs/{id}/events"]["get"] = {
        {"summary", "Server-Sent Events; each data line is a JobEvent"},
        {"responses", {{"200", {{"description", "text/event-stream of JobEvent"}}}}}};
    p["/v1/jobs/{id}/result"]["get"] = {{"summary", "The image (Range supported)"},
                                        {"responses",
                                         {{"200", {{"description", "image/png or image/x-exr"}}},
                                          {"206", {{"description", "a byte range"}}}}}};
    for (const char* path : {"/healthz", "/readyz", "/metrics"})
        p[path]["get"] = {{"responses", {{"200", {{"description", "text/plain"}}}}}};
    return p;
}

}  // namespace

std::string openApiDocument() {
    json schemas = json::object();
    schemasOf(v1::Scene::descriptor()->file(), schemas);
    schemasOf(v1::Job::descriptor()->file(), schemas);
    const json document = {{"openapi", "3.0.3"},
                           {"info", {{"title", "vastray render service"}, {"version", "v1"}}},
                           {"paths", paths()},
                           {"components", {{"schemas", schemas}}}};
    return document.dump(2);
}

}  // namespace vastray::server
