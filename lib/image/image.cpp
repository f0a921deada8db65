#include "image/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/parallel.h"
#include "image/color.h"
#include "image/container.h"

// Notes on conventions that the header leaves implicit:
// - Metadata written: "inlight:color_space" (house name of the in-memory space),
//   "inlight:transfer" ("srgb" or "linear": how integer samples were encoded) and
//   "oiio:ColorSpace" (the name OpenImageIO 2.4 understands: "sRGB" for encoded integer files,
//   "Linear" for linear_srgb, ...). OpenImageIO's TIFF and JPEG writers drop custom attributes,
//   so the two inlight keys are also written into ImageDescription as
//   "inlight:color_space=<name> inlight:transfer=<srgb|linear>", which those formats keep.
//   On reading, a file this module wrote is decoded with the transfer it records and tagged
//   with the space it records. Radiance HDR has no metadata in OpenImageIO: it reads back as
//   linear_srgb, and writing another space there logs a warning.
// - Alpha is passed through as the file stores it: no premultiplication or division is done
//   (PNG and TIFF alpha are read and written unassociated, EXR alpha as stored). Alpha (the last
//   channel of 2- and 4-channel images) is never sRGB-encoded or decoded.

namespace inlight::image {
namespace {

constexpr EnumName<ColorSpace> kColorSpaceNames[] = {
    {ColorSpace::kLinearSrgb, "linear_srgb"},
    {ColorSpace::kSrgb, "srgb"},
    {ColorSpace::kAcescg, "acescg"},
    {ColorSpace::kAces2065_1, "aces2065_1"},
    {ColorSpace::kLinearRec2020, "linear_rec2020"},
    {ColorSpace::kXyzD65, "xyz_d65"},
    {ColorSpace::kRawCamera, "raw_camera"},
    {ColorSpace::kData, "data"},
};

/// "oiio:ColorSpace" for linear (float or linear-integer) files.
constexpr EnumName<ColorSpace> kOiioColorSpaceNames[] = {
    {ColorSpace::kLinearSrgb, "Linear"},
    {ColorSpace::kSrgb, "sRGB"},
    {ColorSpace::kAcescg, "ACEScg"},
    {ColorSpace::kAces2065_1, "ACES2065-1"},
    {ColorSpace::kLinearRec2020, "lin_rec2020"},
    {ColorSpace::kXyzD65, "CIE-XYZ-D65"},
    {ColorSpace::kRawCamera, "Raw"},
    {ColorSpace::kData, "Raw"},
};

enum class Format { kExr, kHdr, kPng, kJpeg, kTiff };

constexpr int kJpegMaxSide = 65500;  // libjpeg's limit; beyond it libjpeg calls exit()

// The metadata value for `key`: the attribute if present, else "key=value" in
// ImageDescription (see the note at the top), else "".
std::string inlight_value(const OIIO::ImageSpec& spec, const std::string& key) {
    std::string v = spec.get_string_attribute(key);
    if (!v.empty()) return v;
    const std::string desc = spec.get_string_attribute("ImageDescription");
    const std::string tag = key + "=";
    size_t at = desc.find(tag);
    if (at == std::string::npos || (at > 0 && desc[at - 1] != ' ')) return "";
    at += tag.size();
    const size_t end = desc.find(' ', at);
    return desc.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

// OIIO error strings end with newlines and sometimes hold several lines; keep one line.
std::string clean(std::string msg) {
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    return msg.empty() ? "unknown OpenImageIO error" : msg;
}

bool is_alpha(int c, int channels) { return (channels == 2 || channels == 4) && c == channels - 1; }

bool is_integer(OIIO::TypeDesc t) {
    switch (t.basetype) {
        case OIIO::TypeDesc::UINT8:
        case OIIO::TypeDesc::INT8:
        case OIIO::TypeDesc::UINT16:
        case OIIO::TypeDesc::INT16:
        case OIIO::TypeDesc::UINT32:
        case OIIO::TypeDesc::INT32:
            return true;
        default:
            return false;
    }
}

// Applies fn(value, channel) to every sample in parallel; chunks are whole rows.
template <typename Fn>
void for_each_sample(Image& img, Fn fn) {
    const int64_t row = static_cast<int64_t>(img.width) * img.channels;
    parallel::for_chunks(img.height, 16, [&](int64_t y0, int64_t y1) {
        for (int64_t i = y0 * row; i < y1 * row; ++i) {
            float& v = img.pixels[static_cast<size_t>(i)];
            v = fn(v, static_cast<int>(i % img.channels));
        }
    });
}

Format format_for(const std::string& path) {
    const std::string ext = fs::extension(path);
    if (ext == "exr") return Format::kExr;
    if (ext == "hdr") return Format::kHdr;
    if (ext == "png") return Format::kPng;
    if (ext == "jpg" || ext == "jpeg") return Format::kJpeg;
    if (ext == "tif" || ext == "tiff") return Format::kTiff;
    throw Error(str(path, ": cannot write: unsupported extension '", ext,
                    "' (use .exr, .hdr, .png, .jpg, .jpeg, .tif or .tiff)"));
}

}  // namespace

void check_writable_name(const std::string& path, const std::string& what) {
    try {
        format_for(path);
    } catch (const Error& e) {
        throw UsageError(str(what, ": ", e.what()));
    }
}

namespace {

// Quantises encoded values in [0, 1] to integers with round-to-nearest; NaN -> 0.
template <typename T>
std::vector<T> quantise(const std::vector<float>& v, double max_code) {
    std::vector<T> out(v.size());
    parallel::for_chunks(static_cast<int64_t>(v.size()), 1 << 16, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            double x = v[static_cast<size_t>(i)];
            x = x >= 0.0 ? std::min(x, 1.0) : 0.0;  // also maps NaN to 0
            out[static_cast<size_t>(i)] = static_cast<T>(std::lround(x * max_code));
        }
    });
    return out;
}

// OpenImageIO's own worker threads (its pool and OpenEXR's decode/encode threads) follow the
// tool's --threads (core/parallel.h), so that --threads 1 runs on one core and scalability
// figures measure what they say. Set before every read and write: cheap, and always current.
void follow_thread_count() {
    const int n = parallel::thread_count();
    OIIO::attribute("threads", n);
    OIIO::attribute("exr_threads", n);
}

// Opens `name` from disk, or from `memory` (an in-memory file whose format OpenImageIO picks by
// the extension of `name`) when it is non-null.
// Before a decoder sees the file, its container is checked (image/container.h) and the most
// samples it can decode to is stored in `max_samples`.
std::unique_ptr<OIIO::ImageInput> open_input(const std::string& name, OIIO::ImageSpec& config,
                                             OIIO::Filesystem::IOProxy* memory,
                                             double* max_samples = nullptr) {
    {
        std::unique_ptr<OIIO::Filesystem::IOFile> file;
        OIIO::Filesystem::IOProxy* source = memory;
        if (!source) {
            fs::check_input_file(name);  // a FIFO or /dev/zero: a decoder would read forever
            file =
                std::make_unique<OIIO::Filesystem::IOFile>(name, OIIO::Filesystem::IOProxy::Read);
            source = file.get();
        }
        if (source->opened()) {
            const double limit =
                check_container(name, source->size(), [source](void* buf, size_t n, uint64_t at) {
                    return source->pread(buf, n, static_cast<int64_t>(at));
                });
            if (max_samples) *max_samples = limit;
        }
    }
    void* proxy = memory;
    if (memory) config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    follow_thread_count();
    // Only the reader of the format the extension names: ImageInput::open would try every other
    // reader OpenImageIO has (about 30, RAW, DICOM, FITS, PSD, ...) when that one fails, so a
    // PNG named .exr was read as a PNG without a word, and a corrupt file reached decoders the
    // project never meant to feed. A name whose extension no reader claims is still recognised
    // by its content.
    std::unique_ptr<OIIO::ImageInput> in;
    const std::string ext = fs::extension(name);
    if (!ext.empty()) in = OIIO::ImageInput::create(ext);
    if (in) {
        OIIO::ImageSpec spec;
        if (!in->open(name, spec, config)) {
            throw Error(str(name, ": cannot open: ", clean(in->geterror())));
        }
        return in;
    }
    (void)OIIO::geterror();  // "could not find a format reader for <ext>": not this file's error
    in = OIIO::ImageInput::open(name, &config);
    if (!in) throw Error(str(name, ": cannot open: ", clean(OIIO::geterror())));
    return in;
}

ImageInfo info_of(const std::string& name, OIIO::Filesystem::IOProxy* memory) {
    OIIO::ImageSpec config;
    auto in = open_input(name, config, memory);
    const OIIO::ImageSpec& spec = in->spec();
    ImageInfo info;
    info.width = spec.width;
    info.height = spec.height;
    info.channels = spec.nchannels;
    info.bits_per_channel =
        spec.get_int_attribute("oiio:BitsPerSample", static_cast<int>(spec.format.size() * 8));
    info.is_float = !is_integer(spec.format);
    info.format = in->format_name();
    in->close();
    return info;
}

}  // namespace

std::string to_string(ColorSpace cs) { return enum_to_string(kColorSpaceNames, cs); }

ColorSpace color_space_from_string(const std::string& name) {
    return enum_from_string(kColorSpaceNames, name, "colour space");
}

Image::Image(int w, int h, int c, ColorSpace cs)
    : width(w), height(h), channels(c), color_space(cs) {
    INLIGHT_CHECK(w > 0 && h > 0 && c > 0) << "image size " << w << "x" << h << "x" << c;
    pixels.assign(static_cast<size_t>(w) * h * c, 0.0f);
}

namespace {

/// Integer codes as floats: `stored[code]` is OIIO's conversion of the code (what a read as
/// float gives), `linear[code]` the sRGB decode of that float (srgb_decode).
struct CodeTables {
    std::vector<float> stored, linear;
};

template <typename Code>
const CodeTables& code_tables() {
    static const CodeTables tables = [] {
        constexpr size_t n = size_t(std::numeric_limits<Code>::max()) + 1;
        std::vector<Code> codes(n);
        for (size_t i = 0; i < n; ++i) codes[i] = static_cast<Code>(i);
        CodeTables t;
        t.stored.resize(n);
        const OIIO::TypeDesc type = sizeof(Code) == 1 ? OIIO::TypeUInt8 : OIIO::TypeUInt16;
        INLIGHT_CHECK(OIIO::convert_pixel_values(type, codes.data(), OIIO::TypeFloat, t.stored.data(), int(n)));
        t.linear.resize(n);
        for (size_t i = 0; i < n; ++i) t.linear[i] = srgb_decode(t.stored[i]);
        return t;
    }();
    return tables;
}

/// img's samples from its codes, sRGB-decoded when `decode` (alpha as stored).
template <typename Code>
void map_codes(const Code* codes, const CodeTables& t, bool decode, Image& img) {
    const int n = img.channels;
    const float* colour = decode ? t.linear.data() : t.stored.data();
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = (is_alpha(int(i % size_t(n)), n) ? t.stored.data() : colour)[codes[i]];
}

constexpr double kMaxSamples = 4.0e9;  // 16 GB of floats: beyond this the header is corrupt

Image read_from(const std::string& path, const ReadOptions& options,
                OIIO::Filesystem::IOProxy* memory) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // pass alpha through as stored
    double max_samples = kMaxSamples;
    auto in = open_input(path, config, memory, &max_samples);
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.deep) throw Error(str(path, ": deep images are not supported"));
    if (spec.depth > 1) throw Error(str(path, ": volume images are not supported"));
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
        throw Error(
            str(path, ": invalid image size ", spec.width, "x", spec.height, "x", spec.nchannels));
    }
    const double samples = double(spec.width) * spec.height * spec.nchannels;
    if (samples > kMaxSamples) {
        throw Error(str(path, ": image too large (", spec.width, "x", spec.height, "x",
                        spec.nchannels, ")"));
    }
    if (samples > max_samples) {  // allocate only what the file's bytes can decode to
        throw Error(str(path, ": header claims ", spec.width, "x", spec.height, "x", spec.nchannels,
                        ", more than the file's bytes can decode to (at most ",
                        static_cast<uint64_t>(max_samples), " samples)"));
    }

    // What the file says about itself (only files this module wrote carry the inlight keys).
    const std::string stored_cs = inlight_value(spec, "inlight:color_space");
    const std::string transfer = inlight_value(spec, "inlight:transfer");
    ColorSpace tagged = ColorSpace::kLinearSrgb;
    bool known = false;
    for (const auto& e : kColorSpaceNames) {
        if (stored_cs == e.name && e.value != ColorSpace::kSrgb) {
            tagged = e.value;
            known = true;
        }
    }
    const bool integer = is_integer(spec.format);
    const bool encoded = integer && transfer != "linear";  // third-party integer files: sRGB
    const bool decode = encoded && options.decode_srgb;
    if (integer && !decode && (encoded || !known)) tagged = ColorSpace::kData;  // values as stored, in [0, 1]

    Image img(spec.width, spec.height, spec.nchannels);
    // Read the stored type (TypeUnknown), then convert: asked for any named type, even the
    // stored one (measured), OIIO 2.4's read_scanlines allocates a 64 MiB staging buffer
    // whatever the image's size (an mmap and munmap per file, which made a BTF of 6561 small
    // images spend most of its time in the kernel). The conversion is OIIO's own, as inside
    // read_image. Files with a type per channel, and those whose stored pixels exceed that
    // buffer (a large HDRI: a copy of it would cost more memory than OIIO's staging), are read
    // as float directly.
    constexpr double kStagingBytes = 64.0 * 1024 * 1024;
    const double stored_bytes = samples * static_cast<double>(spec.format.size());
    bool read = false, decoded = false;
    if (spec.channelformats.empty() && spec.format != OIIO::TypeFloat && stored_bytes <= kStagingBytes) {
        std::vector<unsigned char> stored(static_cast<size_t>(stored_bytes));
        read = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeUnknown, stored.data());
        if (read && spec.format == OIIO::TypeUInt8) {
            // 8- and 16-bit codes through tables of the same conversions: a lookup per sample
            // instead of a pow (the sRGB decode was most of a small PNG's read).
            map_codes(reinterpret_cast<const uint8_t*>(stored.data()), code_tables<uint8_t>(), decode, img);
            decoded = decode;
        } else if (read && spec.format == OIIO::TypeUInt16) {
            map_codes(reinterpret_cast<const uint16_t*>(stored.data()), code_tables<uint16_t>(), decode, img);
            decoded = decode;
        } else if (read) {
            read = OIIO::convert_image(spec.nchannels, spec.width, spec.height, 1, stored.data(),
                                       spec.format, OIIO::AutoStride, OIIO::AutoStride,
                                       OIIO::AutoStride, img.pixels.data(), OIIO::TypeFloat,
                                       OIIO::AutoStride, OIIO::AutoStride, OIIO::AutoStride);
        }
    } else {
        read = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, img.pixels.data());
    }
    if (!read) throw Error(str(path, ": cannot read pixels: ", clean(in->geterror())));
    if (decode && !decoded) {
        const int n = img.channels;
        for_each_sample(img, [n](float v, int c) { return is_alpha(c, n) ? v : srgb_decode(v); });
    }
    img.color_space = tagged;
    in->close();
    return img;
}

}  // namespace

ImageInfo read_info(const std::string& path) { return info_of(path, nullptr); }

ImageInfo read_info_memory(const void* data, size_t size, const std::string& name) {
    OIIO::Filesystem::IOMemReader memory(data, size);
    return info_of(name, &memory);
}

Image read_image(const std::string& path, const ReadOptions& options) {
    return read_from(path, options, nullptr);
}

Image read_image_memory(const void* data, size_t size, const std::string& name,
                        const ReadOptions& options) {
    OIIO::Filesystem::IOMemReader memory(data, size);
    return read_from(name, options, &memory);
}

namespace {

/// Checks and converts `img` for the format of `path`, then calls emit(spec, type, data).
void prepare_write(const std::string& path, const Image& img, const WriteOptions& options,
                   const std::function<void(const OIIO::ImageSpec&, OIIO::TypeDesc, const void*)>& emit) {
    const Format format = format_for(path);
    if (img.width <= 0 || img.height <= 0 || img.channels <= 0 ||
        img.pixels.size() != img.pixel_count() * static_cast<size_t>(img.channels)) {
        throw Error(str(path, ": cannot write: inconsistent image ", img.width, "x", img.height,
                        "x", img.channels, " with ", img.pixels.size(), " values"));
    }
    if (img.color_space == ColorSpace::kSrgb) {
        throw Error(str(path, ": cannot write: in-memory pixels must be linear, but the image is ",
                        "tagged srgb (srgb names an encoding of 8/16-bit files only)"));
    }

    int channels = img.channels;
    const std::vector<float>* src = &img.pixels;
    std::vector<float> expanded;
    if (format == Format::kHdr) {
        if (channels == 1) {
            expanded.resize(img.pixels.size() * 3);
            for (size_t i = 0; i < img.pixels.size(); ++i) {
                expanded[3 * i] = expanded[3 * i + 1] = expanded[3 * i + 2] = img.pixels[i];
            }
            src = &expanded;
            channels = 3;
        } else if (channels != 3) {
            throw Error(str(path, ": Radiance HDR stores 3 channels, got ", channels));
        }
    }
    if (format == Format::kJpeg && channels != 1 && channels != 3) {
        throw Error(str(path, ": JPEG stores 1 or 3 channels, got ", channels));
    }
    if (format == Format::kJpeg && std::max(img.width, img.height) > kJpegMaxSide) {
        throw Error(str(path, ": JPEG stores at most ", kJpegMaxSide, " pixels per side, got ",
                        img.width, "x", img.height));
    }
    if (format == Format::kPng && channels > 4) {
        throw Error(str(path, ": PNG stores 1 to 4 channels, got ", channels));
    }

    const bool integer = format == Format::kPng || format == Format::kJpeg ||
                         (format == Format::kTiff && options.bits != 32);
    if (format == Format::kJpeg && options.bits != 8) {
        throw Error(str(path, ": JPEG stores 8 bits per channel, asked for ", options.bits));
    }
    if (integer && options.bits != 8 && options.bits != 16) {
        throw Error(str(path, ": cannot write ", options.bits,
                        " bits per channel (use 8 or 16; TIFF also takes 32 for float)"));
    }

    OIIO::TypeDesc file_type = OIIO::TypeFloat;
    if (format == Format::kExr && options.exr_half) file_type = OIIO::TypeHalf;
    if (integer) file_type = options.bits == 8 ? OIIO::TypeUInt8 : OIIO::TypeUInt16;

    OIIO::ImageSpec spec(img.width, img.height, channels, file_type);
    if (format == Format::kExr) {
        if (channels == 1) spec.channelnames = {"Y"};
        if (channels == 2) spec.channelnames = {"Y", "A"};
        if (channels == 3) spec.channelnames = {"R", "G", "B"};
        if (channels == 4) spec.channelnames = {"R", "G", "B", "A"};
        spec.alpha_channel = (channels == 2 || channels == 4) ? channels - 1 : -1;
        spec.attribute("compression", "zip");
    }
    if (format == Format::kJpeg) spec.attribute("Compression", "jpeg:95");
    if (format == Format::kPng || format == Format::kTiff) {
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    // OpenImageIO stamps the current time into "DateTime" unless it is set; an empty value
    // suppresses it, so identical inputs give byte-identical files (reproducible outputs).
    spec.attribute("DateTime", "");
    const bool encode = integer && options.encode_srgb;
    const std::string cs_name = to_string(img.color_space);
    const std::string transfer = encode ? "srgb" : "linear";
    spec.attribute("inlight:color_space", cs_name);
    if (integer) spec.attribute("inlight:transfer", transfer);
    const std::string oiio_cs =
        encode ? std::string("sRGB") : enum_to_string(kOiioColorSpaceNames, img.color_space);
    spec.attribute("oiio:ColorSpace", oiio_cs);
    if (format == Format::kTiff || format == Format::kJpeg) {
        spec.attribute("ImageDescription",
                       "inlight:color_space=" + cs_name + " inlight:transfer=" + transfer);
    }
    if (format == Format::kHdr && img.color_space != ColorSpace::kLinearSrgb) {
        log::warn(str(path, ": Radiance HDR keeps no colour space; this ", cs_name,
                      " image will read back as linear_srgb"));
    }

    // Pixel data in the type the file stores (integers quantised here, not by OpenImageIO).
    std::vector<float> encoded_values;
    std::vector<uint8_t> data8;
    std::vector<uint16_t> data16;
    const void* data = src->data();
    OIIO::TypeDesc data_type = OIIO::TypeFloat;
    if (integer) {
        encoded_values = *src;
        if (encode) {
            const int n = channels;
            parallel::for_chunks(static_cast<int64_t>(encoded_values.size()), 1 << 16,
                                 [&](int64_t b, int64_t e) {
                                     for (int64_t i = b; i < e; ++i) {
                                         float& v = encoded_values[static_cast<size_t>(i)];
                                         if (!is_alpha(static_cast<int>(i % n), n)) {
                                             v = srgb_encode(v);
                                         }
                                     }
                                 });
        }
        if (options.bits == 8) {
            data8 = quantise<uint8_t>(encoded_values, 255.0);
            data = data8.data();
            data_type = OIIO::TypeUInt8;
        } else {
            data16 = quantise<uint16_t>(encoded_values, 65535.0);
            data = data16.data();
            data_type = OIIO::TypeUInt16;
        }
    }

    emit(spec, data_type, data);
}

/// Writes prepared pixels to `file` (a path, or a name for the format when `proxy` is set).
void write_prepared(const std::string& path, const std::string& file, const OIIO::ImageSpec& spec,
                    OIIO::TypeDesc data_type, const void* data, OIIO::Filesystem::IOProxy* proxy) {
    follow_thread_count();
    auto out = OIIO::ImageOutput::create(file, proxy);
    if (!out) throw Error(str(path, ": cannot write: ", clean(OIIO::geterror())));
    if (!out->open(file, spec)) throw Error(str(path, ": cannot write: ", clean(out->geterror())));
    if (!out->write_image(data_type, data)) {
        throw Error(str(path, ": cannot write pixels: ", clean(out->geterror())));
    }
    if (!out->close()) throw Error(str(path, ": cannot finish: ", clean(out->geterror())));
}

}  // namespace

void write_image(const std::string& path, const Image& img, const WriteOptions& options) {
    prepare_write(path, img, options, [&](const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* data) {
        fs::write_atomic(path, [&](const std::string& tmp) {
            write_prepared(path, tmp, spec, type, data, nullptr);
        });
    });
}

std::string encode_image(const std::string& name, const Image& img, const WriteOptions& options) {
    std::string bytes;
    prepare_write(name, img, options, [&](const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* data) {
        OIIO::Filesystem::IOVecOutput proxy;
        write_prepared(name, name, spec, type, data, &proxy);
        bytes.assign(proxy.buffer().begin(), proxy.buffer().end());
    });
    return bytes;
}

}  // namespace inlight::image
