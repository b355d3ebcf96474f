#pragma once
// Incremental SHA-256 (OpenSSL's libcrypto underneath; no OpenSSL type here).
#include <cstddef>
#include <memory>
#include <string>

namespace vastray::server {

class Sha256 {
public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;

    void update(const void* data, size_t size);
    // Lowercase hex digest (64 characters); the object is spent afterwards.
    std::string finishHex();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

std::string sha256Hex(const void* data, size_t size);
// 64 lowercase hex digits.
bool isSha256Hex(const std::string& text);

}  // namespace vastray::server
