#include "core/sha256.h"

#include <openssl/evp.h>

#include <fstream>
#include <memory>
#include <vector>

#include "core/check.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight {
namespace {

/// One SHA-256 computation through OpenSSL's EVP interface (libcrypto).
class Sha256 {
  public:
    Sha256() : m_ctx(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
        INLIGHT_CHECK(m_ctx && EVP_DigestInit_ex(m_ctx.get(), EVP_sha256(), nullptr) == 1)
            << "OpenSSL: cannot initialise SHA-256";
    }
    void update(const void* data, size_t size) {
        INLIGHT_CHECK(EVP_DigestUpdate(m_ctx.get(), data, size) == 1) << "OpenSSL: SHA-256 update";
    }
    std::string hex() {
        unsigned char digest[EVP_MAX_MD_SIZE];
        unsigned int length = 0;
        INLIGHT_CHECK(EVP_DigestFinal_ex(m_ctx.get(), digest, &length) == 1)
            << "OpenSSL: SHA-256 final";
        static const char kHex[] = "0123456789abcdef";
        std::string out;
        out.reserve(2 * length);
        for (unsigned int i = 0; i < length; ++i) {
            out += kHex[digest[i] >> 4];
            out += kHex[digest[i] & 15];
        }
        return out;
    }

  private:
    std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> m_ctx;
};

}  // namespace

std::string sha256_hex(const void* data, size_t size) {
    Sha256 h;
    h.update(data, size);
    return h.hex();
}

std::string sha256_file(const std::string& path) {
    fs::check_input_file(path);  // a FIFO or /dev/zero would be hashed forever
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(str(path, ": cannot open for hashing"));
    Sha256 h;
    std::vector<char> buffer(1 << 16);
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        h.update(buffer.data(), static_cast<size_t>(in.gcount()));
    }
    if (in.bad()) throw Error(str(path, ": read error while hashing"));
    return h.hex();
}

}  // namespace inlight
