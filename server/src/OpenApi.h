#pragma once
// /openapi.json: OpenAPI 3.1 description of the HTTP front end (HttpFrontEnd.cpp). Schemas are
// generated from the proto descriptors at run time (OpenApiSchemas.h), descriptions come from
// the proto comments; `openapi-spec-validator` checks it in tests/server/OpenApiTest.cpp.
#include <string>

namespace vastray::server {

// `authRequired`: the server runs with a token (--auth-token-file), so every operation but the
// health checks requires the bearer scheme; else the scheme is declared but not required.
std::string openApiDocument(bool authRequired);

}  // namespace vastray::server
