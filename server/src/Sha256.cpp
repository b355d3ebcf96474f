#include "vastray/server/Sha256.h"

#include <openssl/evp.h>

#include <cassert>

namespace vastray::server {

struct Sha256::Impl {
    EVP_MD_CTX* context = nullptr;
};

Sha256::Sha256() : impl_(std::make_unique<Impl>()) {
    impl_->context = EVP_MD_CTX_new();
    const int ok = impl_->context && EVP_DigestInit_ex(impl_->context, EVP_sha256(), nullptr);
    assert(ok);
    (void)ok;
}

Sha256::~Sha256() { EVP_MD_CTX_free(impl_->context); }

void Sha256::update(const void* data, size_t size) { EVP_DigestUpdate(impl_->context, data, size); }

std::string Sha256::finishHex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_DigestFinal_ex(impl_->context, digest, &length);
    static const char* kHex = "0123456789abcdef";
    std::string hex;
    for (unsigned int i = 0; i < length; ++i) {
        hex += kHex[digest[i] >> 4];
        hex += kHex[digest[i] & 15];
    }
    return hex;
}

std::string sha256Hex(const void* data, size_t size) {
    Sha256 hash;
    hash.update(data, size);
    return hash.finishHex();
}

bool isSha256Hex(const std::string& text) {
    if (text.size() != 64) return false;
    for (char c : text)
        if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
    return true;
}

}  // namespace vastray::server
