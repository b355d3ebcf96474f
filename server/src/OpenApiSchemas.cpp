#include "OpenApiSchemas.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include "ProtoComments.h"
#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

namespace vastray::server {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::EnumDescriptor;
using google::protobuf::FieldDescriptor;
using nlohmann::json;

void describe(json& schema, const std::string& fullName) {
    const std::string text = protoComment(fullName);
    if (!text.empty()) schema["description"] = text;
}

// An enum is its value names (the proto3 JSON mapping); each value's comment is listed in the
// description, as JSON Schema has no place for per-value descriptions.
json enumSchema(const EnumDescriptor* e) {
    json values = json::array();
    std::string description = protoComment(e->full_name());
    for (int i = 0; i < e->value_count(); ++i) {
        const auto* value = e->value(i);
        values.push_back(value->name());
        // Enum values are siblings of their enum in protobuf's scoping, but ProtoComments keys
        // them under the enum (see there).
        const std::string text = protoComment(e->full_name() + "." + value->name());
        if (!text.empty()) description += (description.empty() ? "" : "\n\n") + ("`" + value->name() + "`: " + text);
    }
    json schema = {{"type", "string"}, {"enum", values}};
    if (!description.empty()) schema["description"] = description;
    return schema;
}

// One value of the field, in the proto3 JSON mapping (64-bit integers are strings there).
json valueSchema(const FieldDescriptor* f) {
    switch (f->type()) {
        case FieldDescriptor::TYPE_STRING:
            return {{"type", "string"}};
        case FieldDescriptor::TYPE_BYTES:
            return {{"type", "string"}, {"contentEncoding", "base64"}};
        case FieldDescriptor::TYPE_BOOL:
            return {{"type", "boolean"}};
        case FieldDescriptor::TYPE_FLOAT:
            return {{"type", "number"}, {"format", "float"}};
        case FieldDescriptor::TYPE_DOUBLE:
            return {{"type", "number"}, {"format", "double"}};
        case FieldDescriptor::TYPE_INT64:
        case FieldDescriptor::TYPE_SINT64:
        case FieldDescriptor::TYPE_SFIXED64:
            return {{"type", "string"}, {"format", "int64"}, {"pattern", "^-?[0-9]+$"}};
        case FieldDescriptor::TYPE_UINT64:
        case FieldDescriptor::TYPE_FIXED64:
            return {{"type", "string"}, {"format", "uint64"}, {"pattern", "^[0-9]+$"}};
        case FieldDescriptor::TYPE_UINT32:
        case FieldDescriptor::TYPE_FIXED32:
            return {{"type", "integer"}, {"format", "uint32"}, {"minimum", 0}, {"maximum", 4294967295u}};
        case FieldDescriptor::TYPE_ENUM:
            return openApiSchemaRef(f->enum_type()->full_name());
        case FieldDescriptor::TYPE_MESSAGE:
            if (f->message_type()->full_name() == "google.protobuf.Timestamp")
                return {{"type", "string"}, {"format", "date-time"}};
            return openApiSchemaRef(f->message_type()->full_name());
        default:  // int32, sint32, sfixed32
            return {{"type", "integer"}, {"format", "int32"}};
    }
}

json fieldSchema(const FieldDescriptor* f) {
    json schema;
    if (f->is_map())
        schema = {{"type", "object"}, {"additionalProperties", valueSchema(f->message_type()->map_value())}};
    else if (f->is_repeated())
        schema = {{"type", "array"}, {"items", valueSchema(f)}};
    else
        schema = valueSchema(f);
    describe(schema, f->full_name());
    return schema;
}

void addMessage(const Descriptor* d, json& schemas) {
    if (d->options().map_entry()) return;
    json properties = json::object();
    for (int i = 0; i < d->field_count(); ++i) properties[d->field(i)->name()] = fieldSchema(d->field(i));
    json schema = {{"type", "object"}, {"properties", properties}};
    describe(schema, d->full_name());
    schemas[openApiSchemaName(d->full_name())] = schema;
    for (int i = 0; i < d->nested_type_count(); ++i) addMessage(d->nested_type(i), schemas);
    for (int i = 0; i < d->enum_type_count(); ++i)
        schemas[openApiSchemaName(d->enum_type(i)->full_name())] = enumSchema(d->enum_type(i));
}

void addFile(const google::protobuf::FileDescriptor* file, json& schemas) {
    for (int i = 0; i < file->message_type_count(); ++i) addMessage(file->message_type(i), schemas);
    for (int i = 0; i < file->enum_type_count(); ++i)
        schemas[openApiSchemaName(file->enum_type(i)->full_name())] = enumSchema(file->enum_type(i));
}

}  // namespace

std::string openApiSchemaName(const std::string& fullName) {
    const std::string prefix = "vastray.v1.";
    std::string name = fullName.rfind(prefix, 0) == 0 ? fullName.substr(prefix.size()) : fullName;
    for (char& c : name)
        if (c == '.') c = '_';
    return name;
}

json openApiSchemaRef(const std::string& fullName) {
    return {{"$ref", "#/components/schemas/" + openApiSchemaName(fullName)}};
}

json openApiProtoSchemas() {
    json schemas = json::object();
    addFile(v1::Scene::descriptor()->file(), schemas);
    addFile(v1::Job::descriptor()->file(), schemas);
    return schemas;
}

}  // namespace vastray::server
