#include "oer/api/content_id.hpp"

#include <openssl/evp.h>

#include <array>
#include <memory>

#include "oer/api/rig_options.hpp"
#include "oer/core/error.hpp"

namespace oer::api {

namespace {

std::string digest_hex(const void* data, std::size_t size) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    if (EVP_Digest(data, size, digest.data(), &length, EVP_sha256(), nullptr) != 1) {
        throw Error(ErrorKind::Internal, "SHA-256 failed (OpenSSL EVP_Digest)");
    }
    static constexpr char hex[] = "0123456789abcdef";
    std::string text;
    text.reserve(length * 2);
    for (unsigned int i = 0; i < length; ++i) {
        text += hex[digest[i] >> 4];
        text += hex[digest[i] & 15];
    }
    return text;
}

}  // namespace

std::string sha256_hex(std::span<const std::byte> bytes) {
    return digest_hex(bytes.data(), bytes.size());
}

std::string sha256_hex(std::string_view text) {
    return digest_hex(text.data(), text.size());
}

bool is_content_id(std::string_view text) {
    return text.size() == 64 && text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

std::string rig_id(const std::string& source_digest, const RigOptions& options) {
    return sha256_hex("oer-rig-v1\n" + source_digest + "\n" + rig_options_to_json(options).dump());
}

}  // namespace oer::api
