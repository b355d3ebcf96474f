#pragma once
// gRPC server reflection (grpc.reflection.v1alpha, proto/grpc/reflection/v1alpha) answered from
// protobuf's generated descriptor pool, except that the vastray.v1 files are sent as compiled
// with their comments (ProtoComments.h): `grpcurl describe vastray.v1.RenderService` shows the
// API's documentation, which gRPC's own reflection plugin (generated descriptors) cannot.
#include <memory>
#include <string>
#include <vector>

#include <grpcpp/impl/codegen/service_type.h>

namespace vastray::server {

// The reflection service; `services` are the fully qualified names list_services answers with
// (the reflection service adds its own).
std::unique_ptr<grpc::Service> makeReflectionService(std::vector<std::string> services);

}  // namespace vastray::server
