#pragma once
// /openapi.json: OpenAPI 3.0 description of the HTTP front end. The schemas are generated
// from the proto descriptors at run time, so they cannot drift from the contract.
#include <string>

namespace vastray::server {

std::string openApiDocument();

}  // namespace vastray::server
