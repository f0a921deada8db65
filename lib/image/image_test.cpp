#include "image/image.h"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/parallel.h"
#include "image/color.h"
#include "testing/testing.h"

namespace inlight::image {
namespace {

namespace stdfs = std::filesystem;

// A test image with values spread over [lo, hi], fixed seed.
Image random_image(int w, int h, int c, float lo, float hi, unsigned seed = 1,
                   ColorSpace cs = ColorSpace::kLinearSrgb) {
    return inlight::testing::random_image<Image>(w, h, c, lo, hi, seed, cs);
}

using inlight::testing::error_of;

int file_count(const std::string& dir) {
    int n = 0;
    for ([[maybe_unused]] const auto& e : stdfs::directory_iterator(dir)) ++n;
    return n;
}

std::string starts(const std::string& s, size_t n) { return s.substr(0, std::min(n, s.size())); }

TEST(ColorSpace, NamesRoundTrip) {
    for (ColorSpace cs : {ColorSpace::kLinearSrgb, ColorSpace::kSrgb, ColorSpace::kAcescg,
                          ColorSpace::kAces2065_1, ColorSpace::kLinearRec2020, ColorSpace::kXyzD65,
                          ColorSpace::kRawCamera, ColorSpace::kData}) {
        EXPECT_EQ(color_space_from_string(to_string(cs)), cs);
    }
    EXPECT_EQ(to_string(ColorSpace::kLinearSrgb), "linear_srgb");
    EXPECT_EQ(to_string(ColorSpace::kAces2065_1), "aces2065_1");
}

TEST(ColorSpace, UnknownNameListsTheAcceptedOnes) {
    try {
        color_space_from_string("sRGB-linear");
        FAIL() << "expected UsageError";
    } catch (const UsageError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("sRGB-linear"), std::string::npos) << msg;
        EXPECT_NE(msg.find("linear_srgb"), std::string::npos) << msg;
        EXPECT_NE(msg.find("xyz_d65"), std::string::npos) << msg;
    }
}

TEST(Image, ZeroFilledRowMajorInterleaved) {
    Image img(4, 3, 2);
    EXPECT_EQ(img.pixels.size(), 24u);
    EXPECT_TRUE(std::all_of(img.pixels.begin(), img.pixels.end(), [](float v) { return v == 0; }));
    EXPECT_EQ(img.index(1, 2, 1), (2u * 4 + 1) * 2 + 1);
    img.at(3, 2, 1) = 5;
    EXPECT_EQ(img.pixels.back(), 5);
    EXPECT_EQ(img.color_space, ColorSpace::kLinearSrgb);
}

TEST(ImageIo, OpenImageIoThreadsFollowTheToolsThreadCount) {
    // --threads N (parallel::set_thread_count) must also bound OpenImageIO's pool and
    // OpenEXR's decoder threads, which read_image / write_image set before every file.
    const std::string dir = testing::temp_dir("oiio-threads");
    const Image img = random_image(64, 32, 3, 0.0f, 1.0f);
    for (int threads : {1, 2, 1}) {
        parallel::set_thread_count(threads);
        write_image(dir + "/t.exr", img);
        int oiio = -1, exr = -1;
        ASSERT_TRUE(OIIO::getattribute("threads", oiio));
        ASSERT_TRUE(OIIO::getattribute("exr_threads", exr));
        EXPECT_EQ(oiio, threads) << "after write_image";
        EXPECT_EQ(exr, threads) << "after write_image";
        OIIO::attribute("threads", 7);  // something else changed it: the next read resets it
        EXPECT_EQ(read_image(dir + "/t.exr").pixels, img.pixels);
        ASSERT_TRUE(OIIO::getattribute("threads", oiio));
        EXPECT_EQ(oiio, threads) << "after read_image";
    }
    parallel::set_thread_count(0);
}

TEST(ImageIo, ExrFloatRoundTripIsExact) {
    const std::string dir = testing::temp_dir("exr-float");
    for (int c : {1, 3, 4}) {
        Image img = random_image(37, 21, c, -2.0f, 40000.0f, 10 + c);
        img.pixels[0] = 1e-30f;  // tiny and huge values survive a float file bit for bit
        img.pixels[1] = 3.4e37f;
        const std::string path = dir + "/f" + std::to_string(c) + ".exr";
        write_image(path, img);
        const Image back = read_image(path);
        ASSERT_EQ(back.width, 37);
        ASSERT_EQ(back.height, 21);
        ASSERT_EQ(back.channels, c);
        EXPECT_EQ(back.color_space, ColorSpace::kLinearSrgb);
        EXPECT_EQ(back.pixels, img.pixels) << c << " channels";
        const ImageInfo info = read_info(path);
        EXPECT_EQ(info.format, "openexr");
        EXPECT_TRUE(info.is_float);
        EXPECT_EQ(info.bits_per_channel, 32);
        EXPECT_EQ(info.channels, c);
    }
}

TEST(ImageIo, EncodeImageGivesTheBytesWriteImageWrites) {
    // A caller that stores or counts encoded bytes itself (btf-pca's streamed components) gets
    // exactly the file write_image writes, for 8-bit PNG and half/float EXR.
    const std::string dir = testing::temp_dir("encode-image");
    const Image img = random_image(13, 9, 1, 0.0f, 1.0f, 3);
    WriteOptions linear8, half;
    linear8.encode_srgb = false;
    half.exr_half = true;
    for (const auto& [name, opt] : {std::pair{std::string("a.png"), linear8},
                                    std::pair{std::string("b.exr"), half},
                                    std::pair{std::string("c.exr"), WriteOptions{}}}) {
        write_image(dir + "/" + name, img, opt);
        EXPECT_EQ(encode_image(name, img, opt), fs::read_file(dir + "/" + name)) << name;
    }
}

TEST(ImageIo, ReadsFilesHeldInMemoryLikeFilesOnDisk) {
    // A zip entry or a network buffer decodes exactly as the same bytes read from disk, for
    // every format the BTF reader takes (8/16-bit PNG, JPEG, half EXR).
    const std::string dir = testing::temp_dir("memory-read");
    const Image img = random_image(19, 11, 3, 0.0f, 1.0f, 7);
    struct Case {
        std::string name;
        WriteOptions opt;
    };
    WriteOptions png16, half;
    png16.bits = 16;
    half.exr_half = true;
    for (const Case& c :
         {Case{"a.png", {}}, Case{"b.png", png16}, Case{"c.jpg", {}}, Case{"d.exr", half}}) {
        const std::string path = dir + "/" + c.name;
        write_image(path, img, c.opt);
        const std::string bytes = fs::read_file(path);
        // The name given for memory data need not exist on disk: only its extension counts.
        const std::string name = "archive.zip:entry/" + c.name;
        const Image from_disk = read_image(path);
        const Image from_memory = read_image_memory(bytes.data(), bytes.size(), name);
        EXPECT_EQ(from_memory.pixels, from_disk.pixels) << c.name;
        EXPECT_EQ(from_memory.color_space, from_disk.color_space) << c.name;
        const ImageInfo a = read_info(path), b = read_info_memory(bytes.data(), bytes.size(), name);
        EXPECT_EQ(a.bits_per_channel, b.bits_per_channel) << c.name;
        EXPECT_EQ(a.format, b.format) << c.name;
        // Truncated data is an error that names the entry, never a crash.
        const std::string m =
            error_of([&] { read_image_memory(bytes.data(), bytes.size() / 2, name); });
        EXPECT_NE(m.find(name), std::string::npos) << m;
    }
}

TEST(ImageIo, SameImageGivesByteIdenticalFiles) {
    // No time stamp in the file: reruns (and --threads 1 vs 2) must give identical bytes.
    const std::string dir = testing::temp_dir("exr-bytes");
    const Image img = random_image(16, 8, 3, 0.0f, 1.0f, 3);
    const char* exts[] = {"exr", "tif", "png"};
    for (const char* ext : exts) write_image(dir + "/a." + ext, img);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // cross a clock second
    for (const char* ext : exts) write_image(dir + "/b." + ext, img);
    for (const char* ext : exts) {
        EXPECT_EQ(inlight::fs::read_file(dir + "/a." + ext),
                  inlight::fs::read_file(dir + "/b." + ext))
            << ext;
    }
}

TEST(ImageIo, ExrHalfRoundTripWithinHalfPrecision) {
    // half has an 11-bit significand: round to nearest leaves a relative error <= 2^-11 for
    // normal values (>= 2^-14); its largest finite value is 65504.
    constexpr double kHalfRel = 1.0 / 2048.0;
    const std::string dir = testing::temp_dir("exr-half");
    const Image img = random_image(16, 16, 3, 1e-3f, 60000.0f, 3);
    const std::string path = dir + "/h.exr";
    WriteOptions opt;
    opt.exr_half = true;
    write_image(path, img, opt);
    const ImageInfo info = read_info(path);
    EXPECT_EQ(info.bits_per_channel, 16);
    EXPECT_TRUE(info.is_float);
    const Image back = read_image(path);
    ASSERT_EQ(back.pixels.size(), img.pixels.size());
    double worst = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        worst = std::max(worst, std::fabs(double(back.pixels[i]) - img.pixels[i]) / img.pixels[i]);
    }
    EXPECT_LE(worst, kHalfRel);
    EXPECT_GT(worst, 0.0);  // it really was stored as half
}

// The first channel name in an EXR header's "channels" attribute and the attribute's size
// (OpenEXR file layout: name\0 type\0 int32 size, then name\0 + 16 bytes per channel, \0).
std::pair<std::string, int> exr_first_channel(const std::string& path) {
    const std::string bytes = fs::read_file(path);
    const std::string key("channels\0chlist\0", 16);
    const size_t at = bytes.find(key);
    if (at == std::string::npos) return {"", 0};
    int32_t size = 0;
    std::memcpy(&size, bytes.data() + at + key.size(), 4);
    return {std::string(bytes.c_str() + at + key.size() + 4), size};
}

TEST(ImageIo, ExrChannelNames) {
    const std::string dir = testing::temp_dir("exr-names");
    write_image(dir + "/y.exr", random_image(8, 4, 1, 0, 1));
    const auto [name, size] = exr_first_channel(dir + "/y.exr");
    EXPECT_EQ(name, "Y");
    EXPECT_EQ(size, 2 + 16 + 1);  // exactly one channel
    const Image back = read_image(dir + "/y.exr");
    EXPECT_EQ(back.channels, 1);
    // RGB: EXR sorts channel names, so B comes first; three entries.
    write_image(dir + "/rgb.exr", random_image(8, 4, 3, 0, 1));
    const auto [name3, size3] = exr_first_channel(dir + "/rgb.exr");
    EXPECT_EQ(name3, "B");
    EXPECT_EQ(size3, 3 * (2 + 16) + 1);
}

TEST(ImageIo, HdrRoundTripWithinRgbePrecision) {
    // RGBE stores an 8-bit mantissa per channel with the exponent of the pixel's largest
    // channel: a step of 2^(e-8) with max in [2^(e-1), 2^e), i.e. at most 2^-7 of the largest
    // channel if the encoder truncates (2^-8 if it rounds). Every channel is checked against
    // that bound relative to its pixel's largest channel.
    constexpr double kRgbeRel = 1.0 / 128.0;
    const std::string dir = testing::temp_dir("hdr");
    const Image img = random_image(32, 16, 3, 1e-2f, 30000.0f, 5);
    const std::string path = dir + "/p.hdr";
    write_image(path, img);
    const Image back = read_image(path);
    ASSERT_EQ(back.channels, 3);
    EXPECT_EQ(read_info(path).format, "hdr");
    double worst = 0;
    for (size_t p = 0; p < img.pixel_count(); ++p) {
        const float* a = &img.pixels[3 * p];
        const float* b = &back.pixels[3 * p];
        const double mx = std::max({a[0], a[1], a[2]});
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::fabs(a[k] - b[k]) / mx);
    }
    std::printf("[ hdr ] worst RGBE error %.3g of the pixel maximum (bound %.3g)\n", worst,
                kRgbeRel);
    EXPECT_LE(worst, kRgbeRel);
}

TEST(ImageIo, HdrExpandsOneChannel) {
    const std::string dir = testing::temp_dir("hdr1");
    Image img(4, 2, 1);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = 0.5f * (i + 1);  // exact in RGBE
    write_image(dir + "/g.hdr", img);
    const Image back = read_image(dir + "/g.hdr");
    ASSERT_EQ(back.channels, 3);
    for (size_t p = 0; p < img.pixel_count(); ++p) {
        for (int k = 0; k < 3; ++k) EXPECT_EQ(back.pixels[3 * p + k], img.pixels[p]);
    }
}

TEST(ImageIo, HdrRejectsTwoChannelsAndLeavesNoFile) {
    const std::string dir = testing::temp_dir("hdr2");
    const std::string path = dir + "/x.hdr";
    const std::string msg = error_of([&] { write_image(path, Image(4, 4, 2)); });
    EXPECT_EQ(msg, path + ": Radiance HDR stores 3 channels, got 2");
    EXPECT_EQ(file_count(dir), 0);
}

TEST(ImageIo, Png8And16RoundTripWithinQuantisation) {
    const std::string dir = testing::temp_dir("png");
    for (int bits : {8, 16}) {
        for (int c : {1, 3, 4}) {
            const double max_code = bits == 8 ? 255.0 : 65535.0;
            // Half a code step in the encoded domain, plus float rounding of the curve.
            const double tol = 0.5 / max_code + 1e-6;
            const Image img = random_image(19, 7, c, 0.0f, 1.0f, 20 + c);
            const std::string path =
                dir + "/p" + std::to_string(bits) + "_" + std::to_string(c) + ".png";
            WriteOptions opt;
            opt.bits = bits;
            write_image(path, img, opt);
            const ImageInfo info = read_info(path);
            EXPECT_EQ(info.format, "png");
            EXPECT_EQ(info.bits_per_channel, bits);
            EXPECT_FALSE(info.is_float);
            const Image back = read_image(path);
            ASSERT_EQ(back.channels, c);
            EXPECT_EQ(back.color_space, ColorSpace::kLinearSrgb);
            double worst = 0;
            for (size_t i = 0; i < img.pixels.size(); ++i) {
                const bool alpha = c == 4 && i % 4 == 3;  // alpha is stored linearly
                const double a = alpha ? img.pixels[i] : srgb_encode(img.pixels[i]);
                const double b = alpha ? back.pixels[i] : srgb_encode(back.pixels[i]);
                worst = std::max(worst, std::fabs(a - b));
            }
            EXPECT_LE(worst, tol) << bits << "-bit, " << c << " channels";
        }
    }
}

// Every 8- and 16-bit code, as a third-party PNG holds it (no inlight keys: sRGB-encoded), read
// with and without the sRGB decode, against OpenImageIO's own read as float followed by
// srgb_decode: bit for bit (the reader maps codes through tables of those same conversions).
TEST(ImageIo, EveryIntegerCodeReadsAsOiioFloatThenSrgbDecode) {
    const std::string dir = testing::temp_dir("png-codes");
    for (const OIIO::TypeDesc& type : {OIIO::TypeUInt8, OIIO::TypeUInt16}) {
        for (int c : {1, 2, 3, 4}) {
            const int codes = type == OIIO::TypeUInt8 ? 256 : 65536;
            const int w = 256, h = (codes + w - 1) / w;
            std::vector<uint16_t> wide(size_t(w) * h * c);
            for (size_t i = 0; i < wide.size(); ++i) wide[i] = uint16_t(i / size_t(c));  // pixel k: code k in every channel
            std::vector<uint8_t> narrow(wide.begin(), wide.end());
            const std::string path = dir + "/c" + std::to_string(type.size() * 8) + "_" + std::to_string(c) + ".png";
            {
                auto out = OIIO::ImageOutput::create(path);
                ASSERT_TRUE(out);
                ASSERT_TRUE(out->open(path, OIIO::ImageSpec(w, h, c, type)));
                ASSERT_TRUE(out->write_image(type, type == OIIO::TypeUInt8 ? static_cast<const void*>(narrow.data())
                                                                           : static_cast<const void*>(wide.data())));
                ASSERT_TRUE(out->close());
            }
            std::vector<float> oiio(wide.size());
            {
                OIIO::ImageSpec config;
                config.attribute("oiio:UnassociatedAlpha", 1);  // alpha as stored, as read_image asks
                auto in = OIIO::ImageInput::open(path, &config);
                ASSERT_TRUE(in);
                ASSERT_TRUE(in->read_image(0, 0, 0, c, OIIO::TypeFloat, oiio.data()));
            }
            for (bool decode : {true, false}) {
                ReadOptions ro;
                ro.decode_srgb = decode;
                const Image back = read_image(path, ro);
                ASSERT_EQ(back.pixels.size(), oiio.size());
                EXPECT_EQ(back.color_space, decode ? ColorSpace::kLinearSrgb : ColorSpace::kData);
                size_t differ = 0;
                for (size_t i = 0; i < oiio.size(); ++i) {
                    const bool alpha = (c == 2 || c == 4) && i % size_t(c) == size_t(c - 1);
                    const float want = decode && !alpha ? srgb_decode(oiio[i]) : oiio[i];
                    differ += std::memcmp(&want, &back.pixels[i], sizeof(float)) != 0;
                }
                EXPECT_EQ(differ, 0u) << path << (decode ? ", decoded" : ", as stored");
            }
        }
    }
}

TEST(ImageIo, PngOutOfRangeValuesAreClamped) {
    const std::string dir = testing::temp_dir("png-clamp");
    Image img(3, 1, 1);
    img.pixels = {-0.5f, 7.0f, std::nanf("")};
    write_image(dir + "/c.png", img);
    const Image back = read_image(dir + "/c.png");
    EXPECT_EQ(back.pixels[0], 0.0f);
    EXPECT_NEAR(back.pixels[1], 1.0f, 1e-6);
    EXPECT_EQ(back.pixels[2], 0.0f);
}

TEST(ImageIo, LinearDataPngAndDecodeOff) {
    const std::string dir = testing::temp_dir("png-data");
    constexpr double kHalfStep8 = 0.5 / 255 + 1e-6;
    const Image img = random_image(9, 9, 3, 0.0f, 1.0f, 9, ColorSpace::kData);
    WriteOptions opt;
    opt.encode_srgb = false;
    write_image(dir + "/n.png", img, opt);
    // Written linearly and tagged data: read back as is, whatever decode_srgb says.
    for (bool decode : {true, false}) {
        ReadOptions ro;
        ro.decode_srgb = decode;
        const Image back = read_image(dir + "/n.png", ro);
        EXPECT_EQ(back.color_space, ColorSpace::kData);
        for (size_t i = 0; i < img.pixels.size(); ++i) {
            EXPECT_NEAR(back.pixels[i], img.pixels[i], kHalfStep8);
        }
    }
    // An sRGB-encoded file read with decode_srgb = false gives the stored codes / 255, as data.
    const Image lin = random_image(9, 9, 3, 0.0f, 1.0f, 10);
    write_image(dir + "/s.png", lin);
    ReadOptions raw;
    raw.decode_srgb = false;
    const Image codes = read_image(dir + "/s.png", raw);
    EXPECT_EQ(codes.color_space, ColorSpace::kData);
    for (size_t i = 0; i < lin.pixels.size(); ++i) {
        EXPECT_NEAR(codes.pixels[i], srgb_encode(lin.pixels[i]), kHalfStep8);
        const double code = codes.pixels[i] * 255.0;
        EXPECT_NEAR(code, std::round(code), 1e-3);  // integer codes
    }
}

TEST(ImageIo, TiffRoundTrip) {
    const std::string dir = testing::temp_dir("tiff");
    const Image img = random_image(11, 5, 3, 0.0f, 1.0f, 11);
    WriteOptions opt;
    opt.bits = 16;
    write_image(dir + "/t.tif", img, opt);
    EXPECT_EQ(read_info(dir + "/t.tif").format, "tiff");
    const Image back = read_image(dir + "/t.tif");
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        EXPECT_NEAR(srgb_encode(back.pixels[i]), srgb_encode(img.pixels[i]), 0.5 / 65535 + 1e-6);
    }
    opt.bits = 32;  // float TIFF: exact
    const Image hdr = random_image(11, 5, 3, -1.0f, 100.0f, 12);
    write_image(dir + "/f.tiff", hdr, opt);
    EXPECT_EQ(read_image(dir + "/f.tiff").pixels, hdr.pixels);
}

TEST(ImageIo, JpegRoundTripOfFlatColour) {
    // A flat 16x16 colour has only DC coefficients (and 4:2:0 subsampling of a flat chroma is
    // exact). Quality 95 scales the standard DC quantisers (16, 17) by 0.1 to a step of 2
    // (IJG jcparam.c); DC = 8 x block mean, so the mean moves by <= 1/8 code. The integer
    // RGB -> YCbCr -> RGB conversions round twice (<= 0.5 code each, times the conversion's
    // largest row sum ~1.8 on the way back): within 3 codes in all.
    constexpr double kJpegTol = 3.0 / 255.0;
    const std::string dir = testing::temp_dir("jpeg");
    Image img(16, 16, 3);
    const float rgb[3] = {0.6f, 0.2f, 0.05f};
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = rgb[i % 3];
    write_image(dir + "/j.jpg", img);
    EXPECT_EQ(read_info(dir + "/j.jpg").format, "jpeg");
    const Image back = read_image(dir + "/j.jpg");
    ASSERT_EQ(back.channels, 3);
    double worst = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        worst = std::max(
            worst, std::fabs(double(srgb_encode(back.pixels[i])) - srgb_encode(img.pixels[i])));
    }
    std::printf("[ jpeg ] flat colour worst error %.2f codes (bound 3)\n", worst * 255);
    EXPECT_LE(worst, kJpegTol);
    const std::string msg = error_of([&] { write_image(dir + "/a.jpg", Image(4, 4, 4)); });
    EXPECT_EQ(msg, dir + "/a.jpg: JPEG stores 1 or 3 channels, got 4");
}

TEST(ImageIo, ColorSpaceRestoredFromMetadata) {
    const std::string dir = testing::temp_dir("meta");
    struct Case {
        std::string name;
        ColorSpace cs;
        WriteOptions opt;
    };
    WriteOptions png16;
    png16.bits = 16;
    WriteOptions half;
    half.exr_half = true;
    const Case cases[] = {
        {"a.exr", ColorSpace::kAcescg, {}},    {"b.exr", ColorSpace::kData, half},
        {"c.exr", ColorSpace::kXyzD65, {}},    {"d.png", ColorSpace::kLinearRec2020, png16},
        {"e.tif", ColorSpace::kRawCamera, {}}, {"f.jpg", ColorSpace::kAces2065_1, {}}};
    for (const Case& c : cases) {
        write_image(dir + "/" + c.name, random_image(8, 8, 3, 0.0f, 1.0f, 2, c.cs), c.opt);
        EXPECT_EQ(to_string(read_image(dir + "/" + c.name).color_space), to_string(c.cs)) << c.name;
    }
}

TEST(ImageIo, HdrWarnsThatItDropsTheColourSpace) {
    const std::string dir = testing::temp_dir("hdr-warn");
    log::take_warnings();
    write_image(dir + "/a.hdr", random_image(4, 4, 3, 0.0f, 1.0f, 1, ColorSpace::kAcescg));
    const auto warnings = log::take_warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(dir + "/a.hdr: "), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("acescg"), std::string::npos) << warnings[0];
    EXPECT_EQ(read_image(dir + "/a.hdr").color_space, ColorSpace::kLinearSrgb);
    write_image(dir + "/b.hdr", random_image(4, 4, 3, 0.0f, 1.0f, 1));  // linear_srgb: silent
    EXPECT_TRUE(log::take_warnings().empty());
}

TEST(ImageIo, RefusesSrgbTaggedPixelsAndUnknownExtensions) {
    const std::string dir = testing::temp_dir("refuse");
    EXPECT_EQ(
        starts(error_of([&] { write_image(dir + "/s.png", Image(2, 2, 3, ColorSpace::kSrgb)); }),
               dir.size() + 8),
        dir + "/s.png: ");
    const std::string msg = error_of([&] { write_image(dir + "/x.bmp", Image(2, 2, 3)); });
    EXPECT_NE(msg.find(dir + "/x.bmp: "), std::string::npos) << msg;
    EXPECT_NE(msg.find("unsupported extension 'bmp'"), std::string::npos) << msg;
    Image broken(2, 2, 3);
    broken.pixels.pop_back();
    EXPECT_NE(error_of([&] { write_image(dir + "/b.exr", broken); }).find("inconsistent"),
              std::string::npos);
    WriteOptions b12;
    b12.bits = 12;
    EXPECT_NE(error_of([&] { write_image(dir + "/b.png", Image(2, 2, 3), b12); }).find("12 bits"),
              std::string::npos);
    EXPECT_EQ(file_count(dir), 0);
}

TEST(ImageIo, MissingFileNamesTheFile) {
    const std::string path = testing::temp_dir("missing") + "/sky.exr";
    const std::string msg = error_of([&] { read_image(path); });
    EXPECT_EQ(starts(msg, path.size() + 15), path + ": cannot open: ") << msg;
    EXPECT_EQ(starts(error_of([&] { read_info(path); }), path.size() + 15),
              path + ": cannot open: ");
}

TEST(ImageIo, TruncatedAndCorruptFilesNameTheFile) {
    const std::string dir = testing::temp_dir("corrupt");
    // Truncated EXR: the header is intact, half of the pixel data is gone.
    const std::string exr = dir + "/t.exr";
    write_image(exr, random_image(64, 64, 3, 0.0f, 1.0f, 4));
    stdfs::resize_file(exr, stdfs::file_size(exr) / 2);
    const std::string m1 = error_of([&] { read_image(exr); });
    EXPECT_EQ(starts(m1, exr.size() + 2), exr + ": ") << m1;
    std::printf("[ truncated exr ] %s\n", m1.c_str());

    // PNG whose compressed data is overwritten with garbage (CRC and zlib both fail).
    const std::string png = dir + "/c.png";
    write_image(png, random_image(64, 64, 3, 0.0f, 1.0f, 5));
    std::string bytes = fs::read_file(png);
    for (size_t i = bytes.size() / 3; i < bytes.size() * 2 / 3; ++i) bytes[i] = char(i * 7);
    std::ofstream(png, std::ios::binary) << bytes;
    const std::string m2 = error_of([&] { read_image(png); });
    EXPECT_EQ(starts(m2, png.size() + 2), png + ": ") << m2;
    std::printf("[ corrupt png ] %s\n", m2.c_str());

    // A text file, once with an image extension and once without.
    for (const char* name : {"notes.png", "notes.txt"}) {
        const std::string txt = dir + "/" + name;
        std::ofstream(txt) << "This is not an image.\nJust some text.\n";
        const std::string m3 = error_of([&] { read_image(txt); });
        EXPECT_EQ(starts(m3, txt.size() + 15), txt + ": cannot open: ") << m3;
    }
}

TEST(ImageIo, ReadsAFileOnlyWithTheReaderOfItsExtension) {
    // OpenImageIO's ImageInput::open falls back to every other reader when the extension's own
    // fails: a PNG named .exr was read as a PNG without a word. Now it is a bad EXR.
    const std::string dir = testing::temp_dir("reader");
    const std::string png = dir + "/p.png";
    write_image(png, random_image(8, 4, 3, 0.0f, 1.0f, 7));
    for (const char* ext : {"exr", "hdr", "tif"}) {
        const std::string path = dir + "/p." + ext;
        stdfs::copy_file(png, path, stdfs::copy_options::overwrite_existing);
        const std::string msg = error_of([&] { read_image(path); });
        EXPECT_EQ(starts(msg, path.size() + 15), path + ": cannot open: ") << msg;
        EXPECT_EQ(starts(error_of([&] { read_info(path); }), path.size() + 15),
                  path + ": cannot open: ");
        std::printf("[ png named .%s ] %s\n", ext, msg.c_str());
    }
    EXPECT_NE(error_of([&] { read_image(dir + "/p.exr"); }).find("not an OpenEXR file"),
              std::string::npos);
    // A name no reader claims is still recognised by its content; the same bytes as .png read.
    const std::string unknown = dir + "/p.data";
    stdfs::copy_file(png, unknown);
    EXPECT_EQ(read_image(unknown).pixels, read_image(png).pixels);
}

TEST(ImageIo, FailedWriteKeepsTheOldFileAndLeavesNoTemporary) {
    const std::string dir = testing::temp_dir("atomic");
    const std::string path = dir + "/keep.hdr";
    const Image good = random_image(4, 4, 3, 0.0f, 1.0f, 6);
    write_image(path, good);
    const std::string before = fs::read_file(path);
    EXPECT_THROW(write_image(path, Image(4, 4, 4)), Error);
    EXPECT_EQ(fs::read_file(path), before);
    EXPECT_EQ(file_count(dir), 1);
}

TEST(ImageIo, FailureInsideTheWriterRemovesTheTemporary) {
    // libpng refuses rows wider than 1,000,000 pixels (PNG_USER_WIDTH_MAX): OpenImageIO fails
    // after it created the temporary file, and write_atomic must remove it.
    const std::string dir = testing::temp_dir("atomic-oiio");
    const std::string path = dir + "/wide.png";
    const std::string msg = error_of([&] { write_image(path, Image(1000001, 1, 1)); });
    EXPECT_EQ(starts(msg, path.size() + 2), path + ": ") << msg;
    std::printf("[ png 1000001 px ] %s\n", msg.c_str());
    EXPECT_EQ(file_count(dir), 0);
    // libjpeg would call exit() beyond 65500 pixels; write_image refuses first.
    const std::string jpg = dir + "/wide.jpg";
    EXPECT_EQ(error_of([&] { write_image(jpg, Image(65501, 1, 1)); }),
              jpg + ": JPEG stores at most 65500 pixels per side, got 65501x1");
    EXPECT_EQ(file_count(dir), 0);
}

TEST(RealData, BlenderCityExr) {
    const std::string dir = testing::blender_hdri_dir();
    INLIGHT_SKIP_IF_MISSING(dir, "blender-data HDRIs");
    const std::string path = dir + "/city.exr";
    const ImageInfo info = read_info(path);
    EXPECT_EQ(info.width, 1024);
    EXPECT_EQ(info.height, 512);
    EXPECT_TRUE(info.is_float);
    const Image img = read_image(path);
    ASSERT_EQ(img.width, 1024);
    ASSERT_EQ(img.height, 512);
    EXPECT_GE(img.channels, 3);
    EXPECT_EQ(img.color_space, ColorSpace::kLinearSrgb);
    float mx = 0;
    size_t negative = 0;
    for (float v : img.pixels) {
        mx = std::max(mx, v);
        negative += v < 0;
    }
    std::printf("[ city.exr ] %dx%dx%d, max %.1f, %zu negative samples\n", img.width, img.height,
                img.channels, mx, negative);
    EXPECT_GT(mx, 10000.0f);
    EXPECT_GT(negative, 0u);
}

TEST(RealData, ProbeGraceHdr) {
    const std::string dir = testing::shared_data("probes-latlong");
    INLIGHT_SKIP_IF_MISSING(dir, "shared/data/probes-latlong");
    const Image img = read_image(dir + "/grace.hdr");
    EXPECT_EQ(img.width, 256);
    EXPECT_EQ(img.height, 128);
    EXPECT_EQ(img.channels, 3);
    EXPECT_EQ(img.color_space, ColorSpace::kLinearSrgb);
    EXPECT_TRUE(std::all_of(img.pixels.begin(), img.pixels.end(),
                            [](float v) { return std::isfinite(v) && v >= 0; }));
}

TEST(RealData, BlenderFabricPngIsDecoded) {
    const std::string path =
        "/usr/share/blender/scripts/addons/archimesh/images/fabric_diffuse.png";
    if (!stdfs::exists(path)) GTEST_SKIP() << path << " not found (blender-data); skipping";
    const Image img = read_image(path);
    EXPECT_EQ(img.width, 512);
    EXPECT_EQ(img.height, 512);
    EXPECT_EQ(img.color_space, ColorSpace::kLinearSrgb);
    ReadOptions raw;
    raw.decode_srgb = false;
    const Image codes = read_image(path, raw);
    EXPECT_EQ(codes.color_space, ColorSpace::kData);
    ASSERT_EQ(codes.pixels.size(), img.pixels.size());
    // Decoded = sRGB curve applied to the stored codes, sample by sample.
    double worst = 0, mean_codes = 0, mean_lin = 0;
    const bool has_alpha = img.channels == 2 || img.channels == 4;
    for (size_t i = 0; i < img.pixels.size(); ++i) {
        const bool alpha = has_alpha && int(i % img.channels) == img.channels - 1;
        const float expect = alpha ? codes.pixels[i] : srgb_decode(codes.pixels[i]);
        worst = std::max(worst, double(std::fabs(img.pixels[i] - expect)));
        mean_codes += codes.pixels[i];
        mean_lin += img.pixels[i];
    }
    EXPECT_EQ(worst, 0.0);
    EXPECT_LT(mean_lin, mean_codes);  // decoding darkens mid-tones
}

}  // namespace
}  // namespace inlight::image
