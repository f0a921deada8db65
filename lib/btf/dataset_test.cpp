#include "btf/dataset.h"

#include <gtest/gtest.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "btf/archive.h"
#include "btf/synthetic.h"
#include "core/fs.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

namespace stdfs = std::filesystem;

/// An 8-bit sRGB code is within half a step of the value; decoding multiplies that by at most
/// the curve's largest slope, d/dx ((x + 0.055) / 1.055)^2.4 at x = 1: 2.4 / 1.055 = 2.275.
constexpr double kEightBitTol = 2.275 * 0.5 / 255 + 1e-6;
/// 16-bit codes: the same bound with 65535 steps.
constexpr double kSixteenBitTol = 2.275 * 0.5 / 65535 + 1e-6;

std::string write_text(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

/// A small BTF: 4 lights x 3 views of 7 x 5 pixels, direction sets from files.
struct Small {
    std::string dir;
    OpenOptions open;
    AnalyticBtfOptions opt;
    explicit Small(const std::string& name) {
        dir = testing::temp_dir(name);
        open.light_directions = write_text(dir + "/lights.txt", "0 0\n15 0\n30 90\n60 200\n");
        open.view_directions = write_text(dir + "/views.txt", "0 0\n30 0\n45 120\n");
        opt.width = 7;
        opt.height = 5;
        opt.lights = read_directions(open.light_directions);
        opt.views = read_directions(open.view_directions);
        opt.rank = 3;
    }
};

double max_abs_diff(const image::Image& a, const image::Image& b) {
    double m = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        m = std::max(m, std::abs(double(a.pixels[i]) - b.pixels[i]));
    }
    return m;
}

/// Zips every file under `dir` (relative names) into `zip_path`, with libzip.
void zip_folder(const std::string& dir, const std::string& zip_path) {
    int err = 0;
    zip_t* z = zip_open(zip_path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    std::vector<std::string> keep;  // libzip reads the buffers at zip_close
    for (const auto& e : stdfs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        keep.push_back(fs::read_file(e.path().string()));
        zip_source_t* s = zip_source_buffer(z, keep.back().data(), keep.back().size(), 0);
        ASSERT_GE(zip_file_add(z, stdfs::relative(e.path(), dir).generic_string().c_str(), s, 0),
                  0);
    }
    ASSERT_EQ(zip_close(z), 0);
}

TEST(FolderBtf, ReadsPerViewFoldersWithPrefixAsTheAnalyticTruth) {
    Small s("btf_read_folders");
    const AnalyticBtf truth(s.opt);
    UboWriteOptions wo;
    wo.prefix = "00042 wool ";
    write_ubo2003(truth, s.dir + "/btf", wo);
    write_text(s.dir + "/btf/README.txt", "not an image");
    const auto btf = FolderBtf::open(s.dir + "/btf", s.open);
    EXPECT_EQ(btf->shape().width, 7);
    EXPECT_EQ(btf->shape().height, 5);
    EXPECT_EQ(btf->index().bits_per_channel, 8);
    EXPECT_EQ(btf->index().format, "png");
    EXPECT_EQ(btf->index().ignored, std::vector<std::string>{"README.txt"});
    for (int v = 0; v < 3; ++v) {
        for (int l = 0; l < 4; ++l) {
            EXPECT_LE(max_abs_diff(btf->read_image(l, v), truth.read_image(l, v)), kEightBitTol)
                << l << " " << v;
        }
    }
    // The group matrix holds the same values at column (view_in_group * n_lights + light) * 3 + c.
    Eigen::MatrixXf group;
    btf->read_group({0, 2}, group);
    ASSERT_EQ(group.rows(), 35);
    ASSERT_EQ(group.cols(), 2 * 4 * 3);
    const image::Image img = btf->read_image(3, 2);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(group((4 * 7 + 2), (1 * 4 + 3) * 3 + c), img.at(2, 4, c));
    }
}

TEST(FolderBtf, SixteenBitPngFlatFolderAndHalfExr) {
    Small s("btf_read_formats");
    const AnalyticBtf truth(s.opt);
    UboWriteOptions png16;
    png16.bits = 16;
    png16.per_view_folders = false;
    write_ubo2003(truth, s.dir + "/png16", png16);
    const auto a = FolderBtf::open(s.dir + "/png16", s.open);
    EXPECT_EQ(a->index().bits_per_channel, 16);
    EXPECT_LE(max_abs_diff(a->read_image(1, 2), truth.read_image(1, 2)), kSixteenBitTol);
    UboWriteOptions exr;
    exr.extension = "exr";
    exr.bits = 32;
    write_ubo2003(truth, s.dir + "/exr", exr);
    const auto b = FolderBtf::open(s.dir + "/exr", s.open);
    EXPECT_TRUE(b->index().is_float);
    EXPECT_EQ(max_abs_diff(b->read_image(2, 1), truth.read_image(2, 1)), 0.0);
}

TEST(FolderBtf, ACaptureFolderNamesItsOwnDirectionSetsInCaptureJson) {
    Small s("btf_read_capture_sets");
    const AnalyticBtf truth(s.opt);
    write_ubo2003(truth, s.dir + "/btf");
    // Without the sets the folder's names are not the dome's: refused, naming the file.
    EXPECT_THROW(FolderBtf::open(s.dir + "/btf"), Error);
    stdfs::copy_file(s.open.light_directions, s.dir + "/btf/lights.txt");
    stdfs::copy_file(s.open.view_directions, s.dir + "/btf/views.txt");
    write_text(s.dir + "/btf/capture.json",
               R"({"light_directions": "lights.txt", "view_directions": "views.txt"})");
    const auto btf = FolderBtf::open(s.dir + "/btf");
    ASSERT_EQ(btf->shape().n_lights(), 4);
    ASSERT_EQ(btf->shape().n_views(), 3);
    EXPECT_EQ(btf->shape().lights[3].phi_deg, 200.0);
    EXPECT_EQ(max_abs_diff(btf->read_image(3, 2), FolderBtf::open(s.dir + "/btf", s.open)->read_image(3, 2)), 0.0);
    // A name that leaves the folder, or is not a string, is refused naming capture.json.
    for (const char* bad : {R"({"light_directions": "../lights.txt"})", R"({"light_directions": 3})"}) {
        write_text(s.dir + "/btf/capture.json", bad);
        try {
            FolderBtf::open(s.dir + "/btf");
            ADD_FAILURE() << bad;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("capture.json"), std::string::npos) << e.what();
        }
    }
}

TEST(FolderBtf, ZipFileReadsLikeTheFolderItHolds) {
    Small s("btf_read_zip");
    const AnalyticBtf truth(s.opt);
    write_ubo2003(truth, s.dir + "/btf");
    zip_folder(s.dir + "/btf", s.dir + "/btf.zip");
    const auto folder = FolderBtf::open(s.dir + "/btf", s.open);
    const auto zip = FolderBtf::open(s.dir + "/btf.zip", s.open);
    EXPECT_TRUE(zip->index().is_zip);
    EXPECT_EQ(zip->index().stored_bytes, folder->index().stored_bytes);
    Eigen::MatrixXf a, b;
    folder->read_group({0, 1, 2}, a);
    zip->read_group({0, 1, 2}, b);
    EXPECT_EQ(a, b);
    // The same archive from memory (the fuzzing entry point) reads too.
    const std::string bytes = fs::read_file(s.dir + "/btf.zip");
    EXPECT_NO_THROW(
        fuzz_read_btf_zip(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), s.open));
    // Garbage and a truncated archive are errors, not crashes.
    const std::string bad = "PK\x03\x04 not really a zip";
    EXPECT_NE(testing::error_of([&] {
                  fuzz_read_btf_zip(reinterpret_cast<const uint8_t*>(bad.data()), bad.size());
              }).find("fuzz.zip"),
              std::string::npos);
    testing::error_of([&] {
        fuzz_read_btf_zip(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size() / 2, s.open);
    });
}

TEST(FolderBtf, FullUbo2003DomeByDefault) {
    AnalyticBtfOptions o;
    o.width = 2;
    o.height = 2;
    o.rank = 1;
    const std::string dir = testing::temp_dir("btf_read_dome");
    write_ubo2003(AnalyticBtf(o), dir);
    const auto btf = FolderBtf::open(dir);
    EXPECT_EQ(btf->shape().n_lights(), 81);
    EXPECT_EQ(btf->shape().n_views(), 81);
    EXPECT_EQ(btf->index().files[80 * 81 + 5], "tv075_pv345/tl015 pl240 tv075 pv345.png");
}

TEST(FolderBtf, BadFoldersNameTheFiles) {
    Small s("btf_read_bad");
    const AnalyticBtf truth(s.opt);
    auto fresh = [&](const std::string& name) {
        const std::string d = s.dir + "/" + name;
        write_ubo2003(truth, d);
        return d;
    };
    auto error = [&](const std::string& d) {
        return testing::error_of([&] { FolderBtf::open(d, s.open); });
    };
    {  // a missing image
        const std::string d = fresh("missing");
        stdfs::remove(d + "/tv045_pv120/tl030 pl090 tv045 pv120.png");
        const std::string m = error(d);
        EXPECT_NE(m.find("1 of 12 images are missing: tl030 pl090 tv045 pv120"), std::string::npos)
            << m;
    }
    {  // the same image twice under two names
        const std::string d = fresh("duplicate");
        stdfs::copy_file(d + "/tv030_pv000/tl015 pl000 tv030 pv000.png",
                         d + "/tv030_pv000/copy tl015 pl000 tv030 pv000.png");
        const std::string m = error(d);
        EXPECT_NE(m.find("/copy tl015 pl000 tv030 pv000.png"), std::string::npos) << m;
        EXPECT_NE(m.find("tv030_pv000/tl015 pl000 tv030 pv000.png"), std::string::npos) << m;
        EXPECT_NE(m.find("are the same image"), std::string::npos) << m;
    }
    {  // a light that is not in the set
        const std::string d = fresh("offset");
        stdfs::rename(d + "/tv030_pv000/tl015 pl000 tv030 pv000.png",
                      d + "/tv030_pv000/tl017 pl000 tv030 pv000.png");
        const std::string m = error(d);
        EXPECT_NE(m.find("tl017 pl000 tv030 pv000.png: light direction (17, 0)"), std::string::npos)
            << m;
        EXPECT_NE(m.find("nearest, (15, 0), is 2 deg away"), std::string::npos) << m;
    }
    {  // an image of another size
        const std::string d = fresh("size");
        image::write_image(d + "/tv000_pv000/tl060 pl200 tv000 pv000.png", image::Image(8, 5, 3));
        const std::string m = error(d);
        EXPECT_NE(m.find("tl060 pl200 tv000 pv000.png: 8x5, 3 channels"), std::string::npos) << m;
    }
    {  // another bit depth
        const std::string d = fresh("depth");
        image::WriteOptions w16;
        w16.bits = 16;
        image::write_image(d + "/tv000_pv000/tl060 pl200 tv000 pv000.png", image::Image(7, 5, 3),
                           w16);
        const std::string m = error(d);
        EXPECT_NE(m.find("16-bit png, but"), std::string::npos) << m;
    }
    {  // another channel count
        const std::string d = fresh("channels");
        image::write_image(d + "/tv000_pv000/tl060 pl200 tv000 pv000.png", image::Image(7, 5, 1));
        EXPECT_NE(error(d).find("1 channels"), std::string::npos);
    }
    {  // a file in the folder of another view
        const std::string d = fresh("folder");
        stdfs::rename(d + "/tv030_pv000/tl015 pl000 tv030 pv000.png",
                      d + "/tv000_pv000/tl015 pl000 tv030 pv000.png");
        EXPECT_NE(error(d).find("but its folder names view (0, 0)"), std::string::npos);
    }
    {  // not an image at all
        const std::string d = fresh("corrupt");
        write_text(d + "/tv000_pv000/tl060 pl200 tv000 pv000.png", "garbage");
        EXPECT_NE(error(d).find("tl060 pl200 tv000 pv000.png: cannot open"), std::string::npos);
    }
    EXPECT_NE(error(s.dir + "/nothing-here").find("not a BTF folder"), std::string::npos);
    stdfs::create_directories(s.dir + "/empty");
    EXPECT_NE(error(s.dir + "/empty").find("no BTF images"), std::string::npos);
}

TEST(ViewGroups, NeighboursOnTheDome) {
    const auto& dome = ubo2003_dome();
    EXPECT_EQ(view_groups(dome, 1).size(), 81u);
    ASSERT_EQ(view_groups(dome, 81).size(), 1u);
    EXPECT_EQ(view_groups(dome, 100)[0].size(), 81u);
    const auto g3 = view_groups(dome, 3);
    ASSERT_EQ(g3.size(), 27u);
    std::vector<int> seen(81, 0);
    double widest = 0;
    for (const auto& g : g3) {
        EXPECT_EQ(g.size(), 3u);
        for (int v : g) ++seen[static_cast<size_t>(v)];
        for (int a : g)
            for (int b : g) widest = std::max(widest, angle_between_deg(dome[a], dome[b]));
    }
    EXPECT_EQ(seen, std::vector<int>(81, 1));
    // Neighbours: no group of 3 spans more than two ring spacings (15 deg each).
    EXPECT_LE(widest, 30.0 + 1e-9);
    // 81 views in pairs leave one group with a single view; every pair is two adjacent views
    // (the widest neighbour spacing on the dome is the pole to the 15 deg ring's 15 deg, or
    // 2 asin(sin 15 sin 30) = 14.9 deg along that ring; the outer rings' spacing is below 16.2).
    const auto g2 = view_groups(dome, 2);
    EXPECT_EQ(g2.size(), 41u);
    EXPECT_EQ(std::count_if(g2.begin(), g2.end(), [](const auto& g) { return g.size() == 1; }), 1);
    for (const auto& g : g2) {
        if (g.size() == 2) {
            EXPECT_LT(angle_between_deg(dome[g[0]], dome[g[1]]), 16.2);
        }
    }
}

// The thesis' grouping: k consecutive views of the set's order, the rest in the last group.
TEST(ViewGroups, ConsecutiveAreTheSetsOrderInRunsOfK) {
    const auto& dome = ubo2003_dome();
    const auto g3 = view_groups(dome, 3, ViewGrouping::kConsecutive);
    ASSERT_EQ(g3.size(), 27u);
    for (size_t g = 0; g < g3.size(); ++g)
        EXPECT_EQ(g3[g], (std::vector<int>{int(3 * g), int(3 * g + 1), int(3 * g + 2)}));
    const auto g4 = view_groups(dome, 4, ViewGrouping::kConsecutive);
    ASSERT_EQ(g4.size(), 21u);
    EXPECT_EQ(g4.back(), std::vector<int>{80});
    EXPECT_EQ(view_groups(dome, 200, ViewGrouping::kConsecutive).size(), 1u);
    EXPECT_EQ(view_groups(dome, 1, ViewGrouping::kConsecutive).size(), 81u);
    EXPECT_EQ(to_string(ViewGrouping::kConsecutive), "consecutive");
    EXPECT_EQ(to_string(ViewGrouping::kNeighbours), "neighbours");
}

}  // namespace
}  // namespace inlight::btf
