#include "image/container.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/error.h"

// Expansion bounds, in decoded samples per byte of file (a sample is one channel of one pixel):
// - deflate (zlib) expands at most 1032:1 (258-byte matches coded in 2 bits); an EXR half sample is
//   2 bytes, so ZIP/ZIPS/PXR24 give <= 516 samples per byte. PIZ (wavelet + Huffman whose longest
//   run is 255 repeats in >= 10 bits, <= 410:1) and B44 (fixed 32:14 or 32:3) stay below that.
// - EXR RLE: a run of <= 127 bytes in 2 bytes, <= 63.5:1, so <= 32 samples per byte.
// - DWAA/DWAB nest RLE (<= 63.5:1) and deflate (<= 1032:1): <= 32,766 half samples per byte,
//   rounded up to 2^16.
// - PNG: deflate over rows of 1-bit palette indices that expand to 4 channels: 1032 * 8 * 4.
// - other formats (HDR, TIFF, JPEG, ...): 2^16, above each one's largest ratio.
namespace inlight::image {
namespace {

constexpr double kSamplesPerByteUnknown = 65536.0;
constexpr double kSamplesPerBytePng = 1032.0 * 8 * 4;

struct Reader {
    const std::string& name;
    uint64_t file_size;
    const ReadAt& read_at;

    std::vector<uint8_t> bytes(uint64_t offset, size_t n) const {
        std::vector<uint8_t> out(
            static_cast<size_t>(std::min<uint64_t>(n, file_size - std::min(offset, file_size))));
        if (!out.empty()) out.resize(read_at(out.data(), out.size(), offset));
        return out;
    }
};

uint32_t le32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
int32_t le32s(const uint8_t* p) {
    const uint32_t u = le32(p);
    int32_t s;
    std::memcpy(&s, &u, 4);
    return s;
}
uint32_t be32(const uint8_t* p) {
    return uint32_t(p[3]) | uint32_t(p[2]) << 8 | uint32_t(p[1]) << 16 | uint32_t(p[0]) << 24;
}

// Scan lines per chunk and decoded samples per file byte, by EXR compression code.
int exr_lines_per_chunk(int compression) {
    static const int kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
    return compression >= 0 && compression < 10 ? kLines[compression] : 1;
}
double exr_samples_per_byte(int compression) {
    if (compression == 0) return 0.5;                        // uncompressed: >= 2 bytes per sample
    if (compression == 1) return 32.0;                       // RLE
    if (compression >= 2 && compression <= 7) return 516.0;  // ZIPS ZIP PIZ PXR24 B44 B44A
    return kSamplesPerByteUnknown;                           // DWAA, DWAB, unknown
}

struct ExrPart {
    // OpenEXR reads a header without a compression attribute as ZIP, its Header's default (a
    // 323-byte file of 3997697 x 1 pixels and no such attribute was bounded as "unknown", 2^16
    // samples per byte, and OpenEXR and OpenImageIO then asked for 4 GB: fuzz/regressions/image).
    int compression = 3;
    int64_t width = 0, height = 0;
    int64_t tile_x = 0, tile_y = 0;
    int64_t chunk_count = -1;
    bool tiled = false;
    int channels = 0;              // entries of the channel list
    double samples_per_pixel = 0;  // sum over channels of 1 / (x sampling * y sampling)
};

double check_exr(const Reader& r, uint32_t flags) {
    const bool long_names = flags & 0x400;
    const bool multipart = flags & 0x1000;
    const size_t max_name = long_names ? 255 : 31;
    uint64_t pos = 8;
    std::vector<ExrPart> parts;
    for (;;) {
        const auto first = r.bytes(pos, 1);
        if (first.empty()) throw Error(str(r.name, ": EXR header ends before its end marker"));
        if (first[0] == 0) {  // empty header: end of the multi-part header list
            ++pos;
            if (multipart && !parts.empty()) break;
            throw Error(str(r.name, ": EXR header without attributes"));
        }
        ExrPart part;
        part.tiled = flags & 0x200;
        for (;;) {
            const auto head = r.bytes(pos, 2 * (max_name + 1) + 4);
            if (head.empty()) throw Error(str(r.name, ": EXR header ends before its end marker"));
            if (head[0] == 0) {
                ++pos;
                break;
            }
            const auto cstring = [&](size_t at, const char* what) {
                const auto end = std::find(
                    head.begin() + static_cast<long>(at),
                    head.begin() + static_cast<long>(std::min(head.size(), at + max_name + 1)), 0);
                if (end == head.end() ||
                    static_cast<size_t>(end - head.begin()) >= at + max_name + 1) {
                    throw Error(str(r.name, ": EXR attribute ", what, " at byte ", pos + at,
                                    " is not terminated within ", max_name, " characters"));
                }
                return std::string(head.begin() + static_cast<long>(at), end);
            };
            const std::string attr = cstring(0, "name");
            const std::string type = cstring(attr.size() + 1, "type");
            const size_t size_at = attr.size() + type.size() + 2;
            if (head.size() < size_at + 4)
                throw Error(str(r.name, ": EXR attribute '", attr, "' is cut off"));
            const int32_t size = le32s(&head[size_at]);
            const uint64_t value_at = pos + size_at + 4;
            if (size < 0 || value_at + static_cast<uint64_t>(size) > r.file_size) {
                throw Error(str(r.name, ": EXR attribute '", attr, "' claims ", size,
                                " bytes but the file has ",
                                r.file_size - std::min(value_at, r.file_size), " left"));
            }
            const auto value = [&](size_t n) {
                auto v = r.bytes(value_at, std::min<size_t>(n, static_cast<size_t>(size)));
                if (v.size() < n)
                    throw Error(str(r.name, ": EXR attribute '", attr, "' is too short"));
                return v;
            };
            if (attr == "compression" && type == "compression") part.compression = value(1)[0];
            if (attr == "dataWindow" && type == "box2i") {
                const auto v = value(16);
                part.width = int64_t(le32s(&v[8])) - le32s(&v[0]) + 1;
                part.height = int64_t(le32s(&v[12])) - le32s(&v[4]) + 1;
            }
            if (attr == "tiles" && type == "tiledesc") {
                const auto v = value(8);
                part.tile_x = le32(&v[0]);
                part.tile_y = le32(&v[4]);
            }
            if (attr == "channels" && type == "chlist") {  // name, type, pLinear, 3, xs, ys
                const auto v = r.bytes(value_at, static_cast<size_t>(size));
                for (size_t at = 0; at < v.size() && v[at] != 0;) {
                    const auto end = std::find(v.begin() + static_cast<long>(at), v.end(), 0);
                    const size_t fields = static_cast<size_t>(end - v.begin()) + 1;
                    if (fields + 16 > v.size())
                        throw Error(str(r.name, ": EXR channel list is cut off"));
                    const int32_t xs = le32s(&v[fields + 8]), ys = le32s(&v[fields + 12]);
                    part.samples_per_pixel += 1.0 / (std::max(xs, 1) * double(std::max(ys, 1)));
                    ++part.channels;
                    at = fields + 16;
                }
            }
            if (attr == "chunkCount" && type == "int") part.chunk_count = le32s(value(4).data());
            if (attr == "type" && type == "string") {
                const auto v = r.bytes(value_at, static_cast<size_t>(size));
                part.tiled = std::string(v.begin(), v.end()).find("tiled") != std::string::npos;
            }
            if (type == "stringvector") {  // OpenEXR allocates each string's stated length
                const auto v = r.bytes(value_at, static_cast<size_t>(size));
                for (size_t at = 0; at < v.size();) {
                    if (at + 4 > v.size())
                        throw Error(str(r.name, ": EXR attribute '", attr, "' is cut off"));
                    const int32_t n = le32s(&v[at]);
                    if (n < 0 || at + 4 + static_cast<uint64_t>(n) > v.size()) {
                        throw Error(str(r.name, ": EXR attribute '", attr, "' holds a string of ",
                                        n, " bytes in ", v.size() - at - 4));
                    }
                    at += 4 + static_cast<size_t>(n);
                }
            }
            if (type == "preview") {  // OpenEXR allocates width * height * 4 bytes
                const auto v = value(8);
                const uint64_t need = 8 + 4ull * le32(&v[0]) * le32(&v[4]);
                if (need != static_cast<uint64_t>(size)) {
                    throw Error(str(r.name, ": EXR preview of ", le32(&v[0]), "x", le32(&v[4]),
                                    " does not match its ", size, " bytes"));
                }
            }
            if (type == "idmanifest") {  // OpenEXR inflates it to its stated size
                const auto v = value(4);
                if (le32s(v.data()) < 0 || le32s(v.data()) > 1032.0 * size) {
                    throw Error(str(r.name, ": EXR attribute '", attr, "' claims ", le32s(v.data()),
                                    " bytes from ", size, " compressed"));
                }
            }
            pos = value_at + static_cast<uint64_t>(size);
        }
        parts.push_back(part);
        if (!multipart) break;
    }

    uint64_t chunks = 0;
    double samples_per_byte = 0;
    for (const ExrPart& p : parts) {
        samples_per_byte = std::max(samples_per_byte, exr_samples_per_byte(p.compression));
        if (p.chunk_count >= 0) {
            chunks += static_cast<uint64_t>(p.chunk_count);
        } else if (p.width > 0 && p.height > 0) {
            if (p.tiled && p.tile_x > 0 && p.tile_y > 0) {  // level 0 only: a lower bound
                chunks += static_cast<uint64_t>((p.width + p.tile_x - 1) / p.tile_x) *
                          static_cast<uint64_t>((p.height + p.tile_y - 1) / p.tile_y);
            } else if (!p.tiled) {
                const int lines = exr_lines_per_chunk(p.compression);
                chunks += static_cast<uint64_t>((p.height + lines - 1) / lines);
            }
        }
    }
    // The offset table: 8 bytes per chunk. Compared in double: chunks may be near 2^63.
    if (double(pos) + 8.0 * double(chunks) > double(r.file_size)) {
        throw Error(str(r.name, ": EXR header describes ", chunks,
                        " chunks, but their offset table (", 8.0 * double(chunks),
                        " bytes) does not fit in the ", r.file_size - pos,
                        " bytes after the header"));
    }
    // What the data windows claim, against what the bytes can decode to: refused here, before
    // OpenEXR opens the file, because its open already sizes line buffers by the width (a 205-byte
    // file claiming 7501926 x 1 pixels reserved gigabytes and took seconds under ASan).
    const double max_samples = double(r.file_size - pos - 8 * chunks) * samples_per_byte;
    double claimed = 0;
    for (const ExrPart& p : parts)
        if (p.width > 0 && p.height > 0) claimed += double(p.width) * double(p.height) * p.samples_per_pixel;
    if (claimed > max_samples) {
        const ExrPart& p = parts.front();
        throw Error(str(r.name, ": header claims ", p.width, "x", p.height, "x", p.channels,
                        parts.size() > 1 ? " (first of the parts)" : "",
                        ", more than the file's bytes can decode to (at most ",
                        static_cast<uint64_t>(max_samples), " samples)"));
    }
    return max_samples;
}

void check_png(const Reader& r) {
    uint64_t pos = 8;
    while (pos + 8 <= r.file_size) {
        const auto head = r.bytes(pos, 8);
        if (head.size() < 8) break;
        const uint32_t length = be32(head.data());
        const std::string type(head.begin() + 4, head.end());
        if (length > 0x7fffffffu || pos + 12 + length > r.file_size) {
            throw Error(str(r.name, ": PNG chunk '", type, "' at byte ", pos, " claims ", length,
                            " bytes but the file has ",
                            r.file_size - pos - std::min<uint64_t>(12, r.file_size - pos),
                            " left"));
        }
        if (type == "IEND") break;
        pos += 12 + length;
    }
}

}  // namespace

double check_container(const std::string& name, uint64_t file_size, const ReadAt& read_at) {
    const Reader r{name, file_size, read_at};
    const auto magic = r.bytes(0, 8);
    static const uint8_t kExr[] = {0x76, 0x2f, 0x31, 0x01};
    static const uint8_t kPng[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (magic.size() >= 8 && std::equal(kExr, kExr + 4, magic.begin())) {
        return check_exr(r, le32(&magic[4]));
    }
    if (magic.size() >= 8 && std::equal(kPng, kPng + 8, magic.begin())) {
        check_png(r);
        return double(file_size) * kSamplesPerBytePng;
    }
    return double(file_size) * kSamplesPerByteUnknown;
}

}  // namespace inlight::image
