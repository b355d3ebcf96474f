#include "GrpcReflection.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include <set>

#include "ProtoComments.h"
#include "grpc/reflection/v1alpha/reflection.grpc.pb.h"

namespace vastray::server {
namespace {

namespace refl = grpc::reflection::v1alpha;
using google::protobuf::Descriptor;
using google::protobuf::DescriptorPool;
using google::protobuf::FieldDescriptor;
using google::protobuf::FileDescriptor;

class ReflectionService final : public refl::ServerReflection::Service {
public:
    explicit ReflectionService(std::vector<std::string> services) : services_(std::move(services)) {
        services_.push_back(refl::ServerReflection::service_full_name());
    }

    grpc::Status ServerReflectionInfo(
        grpc::ServerContext* context,
        grpc::ServerReaderWriter<refl::ServerReflectionResponse, refl::ServerReflectionRequest>* stream) override {
        refl::ServerReflectionRequest request;
        while (!context->IsCancelled() && stream->Read(&request)) {
            refl::ServerReflectionResponse response;
            response.set_valid_host(request.host());
            *response.mutable_original_request() = request;
            answer(request, response);
            if (!stream->Write(response)) break;
        }
        return grpc::Status::OK;
    }

private:
    void answer(const refl::ServerReflectionRequest& request, refl::ServerReflectionResponse& response) const {
        const DescriptorPool& pool = *DescriptorPool::generated_pool();
        switch (request.message_request_case()) {
            case refl::ServerReflectionRequest::kFileByFilename:
                return sendFile(pool.FindFileByName(request.file_by_filename()), "file " + request.file_by_filename(),
                                response);
            case refl::ServerReflectionRequest::kFileContainingSymbol:
                return sendFile(pool.FindFileContainingSymbol(request.file_containing_symbol()),
                                "symbol " + request.file_containing_symbol(), response);
            case refl::ServerReflectionRequest::kFileContainingExtension: {
                const auto& ext = request.file_containing_extension();
                const Descriptor* type = pool.FindMessageTypeByName(ext.containing_type());
                const FieldDescriptor* field = type ? pool.FindExtensionByNumber(type, ext.extension_number()) : nullptr;
                return sendFile(field ? field->file() : nullptr,
                                "extension " + std::to_string(ext.extension_number()) + " of " + ext.containing_type(),
                                response);
            }
            case refl::ServerReflectionRequest::kAllExtensionNumbersOfType: {
                const Descriptor* type = pool.FindMessageTypeByName(request.all_extension_numbers_of_type());
                if (!type) return error(grpc::StatusCode::NOT_FOUND, "type " + request.all_extension_numbers_of_type() + " not found", response);
                std::vector<const FieldDescriptor*> extensions;
                pool.FindAllExtensions(type, &extensions);
                auto* numbers = response.mutable_all_extension_numbers_response();
                numbers->set_base_type_name(type->full_name());
                for (const FieldDescriptor* field : extensions) numbers->add_extension_number(field->number());
                return;
            }
            case refl::ServerReflectionRequest::kListServices:
                for (const std::string& name : services_)
                    response.mutable_list_services_response()->add_service()->set_name(name);
                return;
            case refl::ServerReflectionRequest::MESSAGE_REQUEST_NOT_SET:
                break;
        }
        error(grpc::StatusCode::INVALID_ARGUMENT, "the request asks for nothing (message_request is not set)", response);
    }

    // The file and every file it imports, directly or not, each once: a vastray.v1 file as
    // compiled with its comments, any other as protobuf's generated pool holds it.
    static void sendFile(const FileDescriptor* file, const std::string& what, refl::ServerReflectionResponse& response) {
        if (!file) return error(grpc::StatusCode::NOT_FOUND, what + " not found", response);
        auto* files = response.mutable_file_descriptor_response();
        std::set<const FileDescriptor*> sent;
        std::vector<const FileDescriptor*> todo{file};
        while (!todo.empty()) {
            const FileDescriptor* f = todo.back();
            todo.pop_back();
            if (!sent.insert(f).second) continue;
            const auto& commented = commentedProtoFiles();
            if (auto it = commented.find(f->name()); it != commented.end()) {
                files->add_file_descriptor_proto(it->second);
            } else {
                google::protobuf::FileDescriptorProto proto;
                f->CopyTo(&proto);
                files->add_file_descriptor_proto(proto.SerializeAsString());
            }
            for (int i = 0; i < f->dependency_count(); ++i) todo.push_back(f->dependency(i));
        }
    }

    static void error(grpc::StatusCode code, const std::string& message, refl::ServerReflectionResponse& response) {
        response.mutable_error_response()->set_error_code(int(code));
        response.mutable_error_response()->set_error_message(message);
    }

    std::vector<std::string> services_;
};

}  // namespace

std::unique_ptr<grpc::Service> makeReflectionService(std::vector<std::string> services) {
    return std::make_unique<ReflectionService>(std::move(services));
}

}  // namespace vastray::server
