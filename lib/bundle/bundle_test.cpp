// Bundle writing and verification: a round trip, and one test per rejection the reader owes
// the app (path traversal, absolute paths, symlinks out, unknown versions, missing, truncated
// and altered files), each asserting that the message names the file and the problem.
#include "bundle/bundle.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/fs.h"
#include "core/sha256.h"
#include "image/image.h"
#include "testing/testing.h"

namespace inlight::bundle {
namespace {

namespace stdfs = std::filesystem;
using testing::error_of;

// A small valid fabric: three source files in `src`, packed into ROOT/fabrics/weave.
struct Fixture {
    std::string dir, src, root, bundle;
    PackRequest request;

    explicit Fixture(const std::string& name) {
        dir = testing::temp_dir("bundle_" + name);
        src = dir + "/src";
        root = dir + "/bundles";
        bundle = root + "/fabrics/weave";
        stdfs::create_directories(src);
        image::Image img = testing::random_image<image::Image>(8, 4, 3, 0.f, 1.f, 7,
                                                               image::ColorSpace::kLinearSrgb);
        image::write_image(src + "/albedo.png", img);
        image::write_image(src + "/thumbnail.png", image::Image(2, 1, 3));
        fs::write_text_atomic(src + "/material.toml", "specular = \"ggx\"\nalpha = 0.2\n");
        request.kind = Kind::kFabric;
        request.id = "weave";
        request.name = "Test weave";
        request.properties = {{"tile_size_m", 0.05}, {"sh_bands", 3}};
        request.files = {{src + "/albedo.png", "albedo.png", "albedo", -1},
                         {src + "/thumbnail.png", "thumbnail.png", "thumbnail", -1},
                         {src + "/material.toml", "material/material.toml", "material", -1}};
    }
    Manifest write() const { return write_bundle(bundle, request); }
    // Rewrites the manifest through `edit` (as an attacker or a broken tool would).
    void edit_manifest(const std::function<void(nlohmann::json&)>& edit) const {
        const std::string p = bundle + "/manifest.json";
        nlohmann::json j = nlohmann::json::parse(fs::read_file(p));
        edit(j);
        fs::write_text_atomic(p, j.dump(2));
    }
};

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

TEST(Bundle, RoundTripListsEveryFileWithItsHash) {
    Fixture f("roundtrip");
    const Manifest written = f.write();
    const Manifest m = read_bundle(f.bundle);
    ASSERT_EQ(m.files.size(), 3u);
    EXPECT_EQ(m.id, "weave");
    EXPECT_EQ(m.properties["sh_bands"], 3);
    for (const FileEntry& e : m.files) {
        // The hash of each copy is the source's (core/sha256, independent of the bundle code).
        const PackFile* src = nullptr;
        for (const PackFile& p : f.request.files) {
            if (p.path == e.path) src = &p;
        }
        ASSERT_NE(src, nullptr) << e.path;
        EXPECT_EQ(e.sha256, sha256_file(src->source)) << e.path;
        EXPECT_EQ(e.bytes, stdfs::file_size(src->source)) << e.path;
    }
    const FileEntry* albedo = m.find_role("albedo");
    ASSERT_NE(albedo, nullptr);
    EXPECT_EQ(albedo->color_space, "srgb");
    EXPECT_EQ(albedo->media_type, "image/png");
    EXPECT_EQ(albedo->width_px, 8);
    EXPECT_EQ(albedo->height_px, 4);
    EXPECT_EQ(m.total_bytes(), written.total_bytes());
}

TEST(Bundle, SameInputsGiveAByteIdenticalManifest) {
    Fixture f("deterministic");
    f.write();
    const std::string first = fs::read_file(f.bundle + "/manifest.json");
    f.write();  // replaces the bundle in place (atomic exchange)
    EXPECT_EQ(fs::read_file(f.bundle + "/manifest.json"), first);
    // Nothing is left beside it: no temporary or old folder.
    int entries = 0;
    for (const auto& e : stdfs::directory_iterator(f.root + "/fabrics")) {
        ++entries;
        EXPECT_EQ(e.path().filename(), "weave");
    }
    EXPECT_EQ(entries, 1);
}

TEST(Bundle, FailedWriteLeavesTheOldBundleAndNoTemporaryFolder) {
    Fixture f("failed_write");
    f.write();
    const std::string before = manifest_sha256(f.bundle);
    PackRequest bad = f.request;
    bad.files.push_back({f.src + "/does-not-exist.png", "x.png", "normal", -1});
    EXPECT_TRUE(contains(error_of([&] { write_bundle(f.bundle, bad); }), "does-not-exist.png"));
    bad = f.request;
    bad.files.erase(bad.files.begin());  // no albedo: the schema needs one
    EXPECT_TRUE(contains(error_of([&] { write_bundle(f.bundle, bad); }), "role 'albedo'"));
    EXPECT_EQ(manifest_sha256(f.bundle), before);
    read_bundle(f.bundle);
    int entries = 0;
    for (const auto& e : stdfs::directory_iterator(f.root + "/fabrics")) entries += !e.path().empty();
    EXPECT_EQ(entries, 1);
}

TEST(BundleReader, RejectsDotDotPathTraversal) {
    Fixture f("dotdot");
    f.write();
    f.edit_manifest([](nlohmann::json& j) { j["files"][0]["path"] = "../../secret.png"; });
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "manifest.json: files[0].path")) << e;
    EXPECT_TRUE(contains(e, "leaves the bundle")) << e;
    // Also hidden in the middle of a path.
    f.edit_manifest([](nlohmann::json& j) { j["files"][0]["path"] = "a/../../x.png"; });
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "leaves the bundle"));
}

TEST(BundleReader, RejectsAbsolutePaths) {
    Fixture f("absolute");
    f.write();
    f.edit_manifest([](nlohmann::json& j) { j["files"][0]["path"] = "/etc/passwd.png"; });
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "'/etc/passwd.png' is an absolute path")) << e;
}

TEST(BundleReader, RejectsSymlinksOutOfTheBundle) {
    Fixture f("symlink");
    f.write();
    // Replace the listed albedo by a symlink to an identical file outside: same bytes, same
    // hash, so only the containment check can catch it.
    const std::string outside = f.dir + "/outside.png";
    stdfs::copy_file(f.bundle + "/albedo.png", outside);
    stdfs::remove(f.bundle + "/albedo.png");
    stdfs::create_symlink(outside, f.bundle + "/albedo.png");
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "albedo.png: resolves to")) << e;
    EXPECT_TRUE(contains(e, "outside the bundle")) << e;
    // A symlinked folder on the way out is caught the same way.
    stdfs::remove(f.bundle + "/albedo.png");
    stdfs::copy_file(outside, f.bundle + "/albedo.png");
    stdfs::create_directories(f.dir + "/elsewhere");
    stdfs::rename(f.bundle + "/material", f.dir + "/elsewhere/material");
    stdfs::create_directory_symlink(f.dir + "/elsewhere/material", f.bundle + "/material");
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "outside the bundle"));
}

TEST(BundleReader, RejectsABundleFolderLinkedOutOfItsRoot) {
    Fixture f("linked_folder");
    f.write();
    // The whole bundle moved out and linked back: every file inside it checks out, so only the
    // folder's own place in the root can tell.
    const std::string outside = f.dir + "/elsewhere/weave";
    stdfs::create_directories(f.dir + "/elsewhere");
    stdfs::rename(f.bundle, outside);
    stdfs::create_directory_symlink(outside, f.bundle);
    EXPECT_NO_THROW(read_bundle(outside));  // the same folder outside any root is a bundle
    std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, f.bundle + ": resolves through a symlink to " + outside)) << e;
    EXPECT_TRUE(contains(e, "outside the bundle root")) << e;
    // The kind folder linked out: the bundle under it resolves out of the root as well.
    stdfs::remove(f.bundle);
    stdfs::rename(f.root + "/fabrics", f.dir + "/elsewhere/fabrics");
    stdfs::rename(outside, f.dir + "/elsewhere/fabrics/weave");
    stdfs::create_directory_symlink(f.dir + "/elsewhere/fabrics", f.root + "/fabrics");
    e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "outside the bundle root")) << e;
    EXPECT_TRUE(contains(error_of([&] { check_in_root(f.root, "fabrics"); }),
                         f.root + "/fabrics: resolves through a symlink"));
    // A link inside the root to another folder of it is refused too (named as such).
    stdfs::remove(f.root + "/fabrics");
    stdfs::rename(f.dir + "/elsewhere/fabrics", f.root + "/fabrics");
    stdfs::rename(f.bundle, f.root + "/staging");
    stdfs::create_directory_symlink("../staging", f.bundle);
    e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "elsewhere in the bundle root")) << e;
    // Back in place, it reads; a path that does not exist yet passes the check.
    stdfs::remove(f.bundle);
    stdfs::rename(f.root + "/staging", f.bundle);
    EXPECT_NO_THROW(read_bundle(f.bundle));
    EXPECT_NO_THROW(check_in_root(f.root, "devices/none"));
}

TEST(BundleReader, RejectsUnknownVersions) {
    Fixture f("version");
    f.write();
    f.edit_manifest([](nlohmann::json& j) {
        j["version"] = kFormatVersion + 1;
        j["new_key_of_a_later_version"] = true;  // must fail on the version, not on this key
    });
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, str("unknown manifest version ", kFormatVersion + 1,
                                " (this reader knows versions 1 to ", kFormatVersion, ")")))
        << e;
    f.edit_manifest([](nlohmann::json& j) { j["version"] = 0; });
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "unknown manifest version 0"));
    f.edit_manifest([](nlohmann::json& j) { j["version"] = "1"; });
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "unknown manifest version \"1\""));
}

TEST(BundleReader, RejectsMissingFiles) {
    Fixture f("missing");
    f.write();
    stdfs::remove(f.bundle + "/thumbnail.png");
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "weave/thumbnail.png: missing")) << e;
    stdfs::remove(f.bundle + "/manifest.json");
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "manifest.json: missing"));
}

TEST(BundleReader, RejectsTruncatedFiles) {
    Fixture f("truncated");
    f.write();
    const std::string p = f.bundle + "/albedo.png";
    const auto size = stdfs::file_size(p);
    stdfs::resize_file(p, size / 2);
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, str("albedo.png: truncated: ", size / 2, " of ", size, " bytes"))) << e;
}

TEST(BundleReader, RejectsHashMismatches) {
    Fixture f("hash");
    f.write();
    // Same size, one byte changed.
    const std::string p = f.bundle + "/material/material.toml";
    std::string text = fs::read_file(p);
    text[text.size() - 2] = text[text.size() - 2] == '2' ? '3' : '2';
    { std::ofstream(p, std::ios::binary) << text; }
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "material/material.toml: sha256 mismatch")) << e;
}

TEST(BundleReader, RejectsStrayFilesAndSchemaViolations) {
    Fixture f("schema");
    f.write();
    { std::ofstream(f.bundle + "/extra.bin") << "x"; }
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "extra.bin: not listed"));
    stdfs::remove(f.bundle + "/extra.bin");
    const std::pair<std::function<void(nlohmann::json&)>, std::string> cases[] = {
        {[](nlohmann::json& j) { j["colour"] = 1; }, "unknown key 'colour'"},
        {[](nlohmann::json& j) { j["format"] = "zip"; }, "format 'zip'"},
        {[](nlohmann::json& j) { j["files"][0]["sha256"] = "ABC"; }, "files[0].sha256"},
        {[](nlohmann::json& j) { j["files"][0]["role"] = "sparkle"; }, "'sparkle' is not a fabric role"},
        {[](nlohmann::json& j) { j["files"][1]["path"] = "albedo.png"; }, "listed twice"},
        {[](nlohmann::json& j) { j["id"] = "../up"; }, "id '../up'"},
        {[](nlohmann::json& j) { j["total_bytes"] = 1; }, "total_bytes 1"},
        {[](nlohmann::json& j) { j["files"][0]["color_space"] = "data"; }, "color_space"},
        {[](nlohmann::json& j) { j["files"][0]["bytes"] = -3; }, "files[0].bytes"},
    };
    const std::string original = fs::read_file(f.bundle + "/manifest.json");
    for (const auto& [edit, want] : cases) {
        fs::write_text_atomic(f.bundle + "/manifest.json", original);
        f.edit_manifest(edit);
        const std::string e = error_of([&] { read_bundle(f.bundle); });
        EXPECT_TRUE(contains(e, want)) << "want '" << want << "' in: " << e;
    }
    fs::write_text_atomic(f.bundle + "/manifest.json", "{ not json");
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "not valid JSON"));
}

TEST(Manifest, PathCheckAcceptsNestedPathsOnly) {
    EXPECT_NO_THROW(check_relative_path("a/b/c.png", "t"));
    for (const char* bad : {"", "/a", "a//b", "./a", "a/.", "..", "a\\b"}) {
        EXPECT_THROW(check_relative_path(bad, "t"), Error) << bad;
    }
}

}  // namespace
}  // namespace inlight::bundle
