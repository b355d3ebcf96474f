#include <openssl/crypto.h>

#include "vastray/server/FrontEnds.h"

namespace vastray::server {

Result<std::pair<std::string, int>> splitHostPort(const std::string& address) {
    const size_t colon = address.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == address.size())
        return Status::error("'" + address + "': expected HOST:PORT, e.g. 127.0.0.1:8080");
    std::string host = address.substr(0, colon);
    if (host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    const std::string portText = address.substr(colon + 1);
    int port = 0;
    for (char c : portText) {
        if (c < '0' || c > '9' || port > 65535)
            return Status::error("'" + address + "': port must be 0..65535");
        port = port * 10 + (c - '0');
    }
    if (port > 65535) return Status::error("'" + address + "': port must be 0..65535");
    return std::make_pair(host, port);
}

bool bearerMatches(const std::string& header, const std::string& token) {
    const std::string expected = "Bearer " + token;
    return header.size() == expected.size() &&
           CRYPTO_memcmp(header.data(), expected.data(), header.size()) == 0;
}

}  // namespace vastray::server
