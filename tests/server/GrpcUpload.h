#pragma once
// A scene upload through SceneService.UploadScene's client stream, as a client sends it: the
// name (and async) in the first message, the bytes in pieces; `scene` is the response's scene.
// `context` carries the caller's deadline and metadata (a token).
#include <grpcpp/grpcpp.h>

#include <string>

#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {

inline grpc::Status uploadSceneOverGrpc(v1::SceneService::Stub& stub, grpc::ClientContext& context,
                                        const std::string& name, const std::string& bytes, size_t piece, bool async,
                                        v1::Scene* scene) {
    v1::UploadSceneResponse response;
    auto writer = stub.UploadScene(&context, &response);
    for (size_t at = 0; at < bytes.size(); at += piece) {
        v1::UploadSceneRequest message;
        if (at == 0) {
            message.set_name(name);
            message.set_async(async);
        }
        message.set_data(bytes.substr(at, piece));
        if (!writer->Write(message)) break;  // the server ended the stream: Finish says why
    }
    writer->WritesDone();
    grpc::Status status = writer->Finish();
    *scene = response.scene();
    return status;
}

inline grpc::Status uploadSceneOverGrpc(v1::SceneService::Stub& stub, const std::string& name,
                                        const std::string& bytes, size_t piece, bool async, v1::Scene* scene) {
    grpc::ClientContext context;
    return uploadSceneOverGrpc(stub, context, name, bytes, piece, async, scene);
}

}  // namespace vastray::test
