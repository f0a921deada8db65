// image/container.h: what an image file can hold, checked from its bytes before a decoder sees
// it. OpenEXR and libpng trust a length field and allocate it before reading it: a 604-byte EXR
// whose string attribute claims 1.9 GB, or a PNG tEXt chunk claiming 1.7 GB, costs that much
// memory (found by fuzz/image_fuzz and fuzz/btf_fuzz). Every length is checked against the
// bytes that follow it, and the decoded size against what the file's compression can expand to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace inlight::image {

/// Reads up to `size` bytes at `offset` into `buf`; returns the count read.
using ReadAt = std::function<size_t(void* buf, size_t size, uint64_t offset)>;

/// Checks the container of an image file of `file_size` bytes, recognised by its content (EXR,
/// PNG; other formats pass): every EXR attribute and PNG chunk must fit in the file, EXR string
/// vectors, previews and ID manifests must fit in their attribute, and the EXR chunk offset table
/// must fit. Throws Error "<name>: ..." naming the field. Returns the most samples (pixels times
/// channels) the file can decode to: its size times the largest expansion of its compression
/// (deflate at most 1032:1; see container.cpp for each format).
double check_container(const std::string& name, uint64_t file_size, const ReadAt& read_at);

}  // namespace inlight::image
