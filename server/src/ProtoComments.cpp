#include "ProtoComments.h"

#include <google/protobuf/descriptor.pb.h>

#include <sstream>
#include <vector>

namespace vastray::server {
namespace {

const unsigned char kDescriptorSet[] = {
#include "vastray_v1_descriptor_set.inc"
};

using google::protobuf::DescriptorProto;
using google::protobuf::EnumDescriptorProto;
using google::protobuf::FileDescriptorProto;
using Path = std::vector<int>;

// Field numbers in descriptor.proto that SourceCodeInfo paths are made of.
constexpr int kFileMessage = 4, kFileEnum = 5, kFileService = 6;
constexpr int kMessageField = 2, kMessageNested = 3, kMessageEnum = 4;
constexpr int kEnumValue = 2, kServiceMethod = 2;

std::string joinLines(const std::string& comment) {
    std::istringstream in(comment);
    std::string out;
    for (std::string line; std::getline(in, line);) {
        const size_t begin = line.find_first_not_of(" \t");
        if (begin == std::string::npos) continue;
        const size_t end = line.find_last_not_of(" \t\r");
        if (!out.empty()) out += ' ';
        out += line.substr(begin, end - begin + 1);
    }
    return out;
}

class Collector {
public:
    Collector(const FileDescriptorProto& file, std::map<std::string, std::string>& out) : out_(out) {
        for (const auto& location : file.source_code_info().location()) {
            const std::string& text =
                location.has_leading_comments() ? location.leading_comments() : location.trailing_comments();
            if (!text.empty()) comments_[Path(location.path().begin(), location.path().end())] = joinLines(text);
        }
        const std::string prefix = file.package().empty() ? "" : file.package() + ".";
        for (int i = 0; i < file.message_type_size(); ++i)
            message(file.message_type(i), prefix + file.message_type(i).name(), {kFileMessage, i});
        for (int i = 0; i < file.enum_type_size(); ++i)
            enumeration(file.enum_type(i), prefix + file.enum_type(i).name(), {kFileEnum, i});
        for (int s = 0; s < file.service_size(); ++s) {
            const std::string name = prefix + file.service(s).name();
            note(name, {kFileService, s});
            for (int m = 0; m < file.service(s).method_size(); ++m)
                note(name + "." + file.service(s).method(m).name(), {kFileService, s, kServiceMethod, m});
        }
    }

private:
    void note(const std::string& name, const Path& path) {
        auto it = comments_.find(path);
        if (it != comments_.end()) out_[name] = it->second;
    }

    static Path child(Path path, int kind, int index) {
        path.push_back(kind);
        path.push_back(index);
        return path;
    }

    void message(const DescriptorProto& m, const std::string& name, const Path& path) {
        note(name, path);
        for (int i = 0; i < m.field_size(); ++i) note(name + "." + m.field(i).name(), child(path, kMessageField, i));
        for (int i = 0; i < m.nested_type_size(); ++i)
            message(m.nested_type(i), name + "." + m.nested_type(i).name(), child(path, kMessageNested, i));
        for (int i = 0; i < m.enum_type_size(); ++i)
            enumeration(m.enum_type(i), name + "." + m.enum_type(i).name(), child(path, kMessageEnum, i));
    }

    // Enum values are scoped like C++: "vastray.v1.JobState.JOB_STATE_QUEUED" names JOB_STATE_QUEUED
    // of JobState here.
    void enumeration(const EnumDescriptorProto& e, const std::string& name, const Path& path) {
        note(name, path);
        for (int i = 0; i < e.value_size(); ++i) note(name + "." + e.value(i).name(), child(path, kEnumValue, i));
    }

    std::map<Path, std::string> comments_;
    std::map<std::string, std::string>& out_;
};

// The embedded descriptor set, parsed once for both readers below. Compiled in by the build:
// failing to parse it is a build defect, which the tests catch (every described element would
// lose its description, reflection its files); it reads as an empty set.
const google::protobuf::FileDescriptorSet& descriptorSet() {
    static const google::protobuf::FileDescriptorSet set = [] {
        google::protobuf::FileDescriptorSet parsed;
        if (!parsed.ParseFromArray(kDescriptorSet, int(sizeof kDescriptorSet))) parsed.Clear();
        return parsed;
    }();
    return set;
}

std::map<std::string, std::string> parse() {
    std::map<std::string, std::string> comments;
    for (const FileDescriptorProto& file : descriptorSet().file()) Collector(file, comments);
    return comments;
}

// protoc fills every field's json_name ("sceneId") in a descriptor set, the generated pool's
// descriptors leave it unset: cleared, so that clients print the names they printed before
// reflection sent these files (grpcurl prints scene_id), as the field's own name.
void clearJsonNames(DescriptorProto& message) {
    for (auto& field : *message.mutable_field()) field.clear_json_name();
    for (auto& field : *message.mutable_extension()) field.clear_json_name();
    for (DescriptorProto& nested : *message.mutable_nested_type()) clearJsonNames(nested);
}
void clearJsonNames(FileDescriptorProto& file) {
    for (DescriptorProto& message : *file.mutable_message_type()) clearJsonNames(message);
    for (auto& field : *file.mutable_extension()) field.clear_json_name();
}

}  // namespace

const std::map<std::string, std::string>& protoComments() {
    static const std::map<std::string, std::string> comments = parse();
    return comments;
}

const std::map<std::string, std::string>& commentedProtoFiles() {
    static const std::map<std::string, std::string> files = [] {
        std::map<std::string, std::string> serialized;
        for (FileDescriptorProto file : descriptorSet().file()) {
            clearJsonNames(file);
            serialized[file.name()] = file.SerializeAsString();
        }
        return serialized;
    }();
    return files;
}

std::string protoComment(const std::string& fullName) {
    auto it = protoComments().find(fullName);
    return it == protoComments().end() ? std::string() : it->second;
}

}  // namespace vastray::server
