// core/sha256.h: SHA-256 (FIPS 180-4) of files, for the run report's input list and bundle
// manifests; computed by OpenSSL's libcrypto (EVP), not by hand.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace inlight {

/// Lower-case hex SHA-256 of a byte buffer.
std::string sha256_hex(const void* data, size_t size);
/// Lower-case hex SHA-256 of a file's contents. Throws Error naming the file if unreadable.
std::string sha256_file(const std::string& path);

}  // namespace inlight
