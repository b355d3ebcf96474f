#pragma once
// The browser page of `vastray serve` (server/web/: index.html, app.css, and app.ts compiled to
// app.js by tsc at build time), embedded in the binary and served at "/". No bearer token is
// needed for these files: the page asks for it and sends it with every /v1 call.
#include <string>

namespace httplib {
class Server;
}

namespace vastray::server {

// True for the paths of the page's files ("/", "/index.html", "/app.js", "/app.css").
bool isWebPagePath(const std::string& path);

// GET routes for the page's files: Content-Type, a Content-Security-Policy that allows only the
// page's own origin, `Cache-Control: no-cache` with an ETag (a reload costs a 304).
void addWebPageRoutes(httplib::Server& server);

}  // namespace vastray::server
