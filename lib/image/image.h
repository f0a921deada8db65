// image/image.h: in-memory images (linear float, each knowing its colour space) and file I/O
// through OpenImageIO: EXR, HDR, PNG, JPEG, TIFF.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace inlight::image {

/// Colour spaces by their house-style names (see docs/conventions.md).
enum class ColorSpace {
    kLinearSrgb,     ///< "linear_srgb": Rec.709 primaries, D65, linear (the in-memory default)
    kSrgb,           ///< "srgb": sRGB-encoded; only for 8-bit I/O, never for pixels in memory
    kAcescg,         ///< "acescg"
    kAces2065_1,     ///< "aces2065_1"
    kLinearRec2020,  ///< "linear_rec2020"
    kXyzD65,         ///< "xyz_d65"
    kRawCamera,      ///< "raw_camera": camera RGB before any colour transform
    kData,           ///< "data": not colour (directions, solid angles, normals, masks, errors)
};

/// "linear_srgb", ... as listed above.
std::string to_string(ColorSpace cs);
/// Inverse of to_string. Throws UsageError naming the accepted names on an unknown name.
ColorSpace color_space_from_string(const std::string& name);

/// A float image: `pixels` holds width*height*channels values, row-major, row 0 on top,
/// channels interleaved. Pixel centres are at (x + 0.5, y + 0.5).
struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    ColorSpace color_space = ColorSpace::kLinearSrgb;
    std::vector<float> pixels;

    Image() = default;
    /// Zero-filled image. Precondition: width, height, channels > 0 (checked).
    Image(int width, int height, int channels, ColorSpace cs = ColorSpace::kLinearSrgb);

    size_t index(int x, int y, int c) const {
        return (static_cast<size_t>(y) * width + x) * channels + c;
    }
    float& at(int x, int y, int c) { return pixels[index(x, y, c)]; }
    float at(int x, int y, int c) const { return pixels[index(x, y, c)]; }
    size_t pixel_count() const { return static_cast<size_t>(width) * height; }
};

/// How integer-valued files are interpreted on reading.
struct ReadOptions {
    /// 8- and 16-bit integer files are sRGB-decoded to linear unless this is false (then they
    /// are read as linear values in [0, 1], e.g. for normal maps and data).
    bool decode_srgb = true;
};

/// Basic facts about a file without reading its pixels.
struct ImageInfo {
    int width = 0;
    int height = 0;
    int channels = 0;
    int bits_per_channel = 0;  ///< 8, 16 or 32 (float); 16 for half
    bool is_float = false;
    std::string format;  ///< OpenImageIO format name: "openexr", "hdr", "png", ...
};

/// Reads a file's header. Throws Error naming the file if it cannot be opened.
ImageInfo read_info(const std::string& path);

/// read_info of an image file held in memory (`data`, `size` bytes, e.g. a zip entry). The
/// format is chosen by the extension of `name`, which also names the file in errors. Only the
/// header needs to be present. Throws Error naming `name`.
ImageInfo read_info_memory(const void* data, size_t size, const std::string& name);

/// Reads any format OpenImageIO reads into linear float. Float formats (EXR, HDR, float TIFF)
/// are taken as linear_srgb; integer formats are sRGB-decoded (see ReadOptions) and tagged
/// linear_srgb, or tagged data when decode_srgb is false. Throws Error naming the file.
/// Files written by write_image carry their colour space and integer encoding in metadata:
/// the space is restored, and integer files written with encode_srgb = false are read back
/// as stored (never decoded). Alpha (the last of 2 or 4 channels) is passed through as the
/// file stores it: never decoded, premultiplied or divided. Reads subimage 0, mip level 0.
Image read_image(const std::string& path, const ReadOptions& options = {});

/// read_image of an image file held in memory; the format is chosen by the extension of
/// `name`, which also names the file in errors. `data` is not kept after the call. Truncated or
/// corrupt data throws Error naming `name`.
Image read_image_memory(const void* data, size_t size, const std::string& name,
                        const ReadOptions& options = {});

/// How to write.
struct WriteOptions {
    /// For PNG/JPEG/TIFF: 8 or 16 bits per channel (JPEG: 8 only; TIFF also takes 32 for a
    /// linear float TIFF); EXR is always half or float (see below), HDR always RGBE.
    int bits = 8;
    /// EXR only: write 16-bit half instead of 32-bit float.
    bool exr_half = false;
    /// For integer formats: encode linear values with the sRGB curve (true) or write them
    /// linearly (false, for data images). Values are clamped to [0, 1] (NaN to 0) and rounded
    /// to the nearest code. Alpha (the last of 2 or 4 channels) is never encoded.
    bool encode_srgb = true;
};

/// Writes by extension (.exr .hdr .png .jpg/.jpeg .tif/.tiff) atomically: a temporary file is
/// renamed into place, so a failure never leaves a partial file. The colour space is stored in
/// the file's metadata ("oiio:ColorSpace" and "inlight:color_space"). Throws Error on failure.
/// Channels: EXR names 1 -> Y, 2 -> Y,A, 3 -> R,G,B, 4 -> R,G,B,A; HDR takes 3 (1 is expanded
/// to grey RGB, others are an Error) and keeps no colour space (anything but linear_srgb logs
/// a warning); PNG takes 1-4; JPEG 1 or 3 and at most 65500 pixels per side.
void write_image(const std::string& path, const Image& img, const WriteOptions& options = {});

/// Throws UsageError naming `what` unless write_image can write a file named `path` (its
/// extension names a format it writes): for checking an output before any work.
void check_writable_name(const std::string& path, const std::string& what);

/// The bytes write_image would write for a file named `name` (its extension picks the format:
/// PNG, EXR, JPEG, TIFF), in memory, so a caller can count or store them itself. Throws Error
/// naming `name` on failure.
std::string encode_image(const std::string& name, const Image& img, const WriteOptions& options = {});

}  // namespace inlight::image
