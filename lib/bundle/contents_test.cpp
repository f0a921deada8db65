// The manifests inside a fabric bundle (check_contents): a compressed BTF whose components are
// bundled in its stream order, exported GLES variants whose manifests name files the bundle
// holds; one test per rejection (wrong stream order, a missing or mis-roled file, a tampered
// shader), and version 1 manifests, which predate the roles these need.
#include "bundle/contents.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <utility>
#include <vector>

#include "bundle/bundle.h"
#include "core/fs.h"
#include "core/sha256.h"
#include "image/image.h"
#include "testing/testing.h"

namespace inlight::bundle {
namespace {

namespace stdfs = std::filesystem;
using testing::error_of;

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

// A minimal fabric bundle request (albedo, thumbnail, material) with sources under DIR/src.
struct Fabric {
    std::string dir, src, bundle;
    PackRequest request;

    explicit Fabric(const std::string& name) {
        dir = testing::temp_dir("bundle_contents_" + name);
        src = dir + "/src";
        bundle = dir + "/bundles/fabrics/weave";
        stdfs::create_directories(src);
        image::write_image(src + "/albedo.png", image::Image(4, 4, 3));
        image::write_image(src + "/thumbnail.png", image::Image(2, 2, 3));
        fs::write_text_atomic(src + "/material.toml", "specular = \"ggx\"\nalpha = 0.2\n");
        request.id = "weave";
        request.name = "Weave";
        request.files = {{src + "/albedo.png", "albedo.png", "albedo", -1},
                         {src + "/thumbnail.png", "thumbnail.png", "thumbnail", -1},
                         {src + "/material.toml", "material.toml", "material", -1}};
    }
    void add(const std::string& name, const std::string& text, const std::string& path,
             const std::string& role, int stream_index = -1) {
        stdfs::create_directories(stdfs::path(src + "/" + name).parent_path());
        fs::write_text_atomic(src + "/" + name, text);
        request.files.push_back({src + "/" + name, path, role, stream_index});
    }
    void add_image(const std::string& name, const std::string& role, int stream_index = -1) {
        image::write_image(src + "/" + name, image::Image(2, 2, 3, image::ColorSpace::kData));
        request.files.push_back({src + "/" + name, "btf/" + name, role, stream_index});
    }

    // A compressed BTF as btf-pca writes it: two view groups of two components, streamed in
    // `stream` ([group, component] pairs); each component is bundled at its stream position.
    void add_btf(const std::vector<std::pair<int, int>>& stream) {
        nlohmann::json groups = nlohmann::json::array();
        for (int g = 0; g < 2; ++g) {
            const std::string mean = str("g00", g, "-mean.png");
            add_image(mean, "btf_mean");
            nlohmann::json comps = nlohmann::json::array();
            for (int c = 0; c < 2; ++c) comps.push_back({{"file", str("g00", g, "-c0", c, ".png")}});
            groups.push_back({{"mean", {{"file", mean}}}, {"components", comps}});
        }
        nlohmann::json order = nlohmann::json::array();
        for (size_t k = 0; k < stream.size(); ++k) {
            const auto [g, c] = stream[k];
            order.push_back({g, c});
            add_image(groups[g]["components"][c]["file"], "btf_component", static_cast<int>(k));
        }
        add("btf-pca.json",
            nlohmann::json({{"format", "inlight-btf-pca"}, {"groups", groups}, {"stream", order},
                            {"weights", {{"file", "weights.bin"}}}})
                .dump(),
            "btf/btf-pca.json", "btf_manifest");
        add("weights.bin", std::string(64, '\1'), "btf/weights.bin", "btf_weights");
    }

    // The BTF's GLES export as btf-pca export-gles --atlases none writes it, beside add_btf's
    // btf-pca.json: one variant, the matrices, and per group an atlas slab whose channels name
    // the group's mean and two components (the fourth unused); `edit` changes the manifest.
    void add_btf_gles(const std::function<void(nlohmann::json&)>& edit = {}) {
        add("btf-es300-highp.vert", "#version 300 es\nvoid main() {}\n", "btf/btf-es300-highp.vert",
            "btf_gles_vertex");
        add("btf-es300-highp.frag", "#version 300 es\nvoid main() {}\n", "btf/btf-es300-highp.frag",
            "btf_gles_fragment");
        add("lighting-matrices.bin", std::string(96, '\3'), "btf/lighting-matrices.bin", "btf_gles_matrices");
        nlohmann::json groups = nlohmann::json::array();
        for (int g = 0; g < 2; ++g) {
            groups.push_back({{"file", nullptr},
                              {"channels", {{{"file", str("g00", g, "-mean.png")}}, {{"file", str("g00", g, "-c00.png")}},
                                            {{"file", str("g00", g, "-c01.png")}}, {{"file", nullptr}}}}});
        }
        nlohmann::json j = {
            {"format", "inlight_btf_gles_export"},
            {"variants", {{{"name", "btf-es300-highp"}, {"vertex_shader", "btf-es300-highp.vert"},
                           {"fragment_shader", "btf-es300-highp.frag"}}}},
            {"matrices", {{"file", "lighting-matrices.bin"}, {"bytes", 96}}},
            {"textures", {{"atlas_files", false}, {"groups", groups}}},
            {"load", {{{"capability", "OpenGL ES 3.0 or later"}, {"variant", "btf-es300-highp"}},
                      {{"capability", "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH"}, {"variant", nullptr}}}}};
        if (edit) edit(j);
        add("btf-gles.json", j.dump(), "btf/btf-gles.json", "btf_gles_manifest");
    }

    // One exported GLES variant as render/brdf-sh-bake --export-gles write it (manifest naming
    // its vertex and fragment shaders and table data), plus the index of the variants.
    // A Lambert material has no table: its manifest's brdf_data is null.
    // `texture_px` > 0: the variant binds an albedo texture of texture_px^2 RGBA8 texels from
    // shaders/<name>.albedo.png, an 8-bit RGBA PNG of `png_px` x texture_px pixels.
    void add_shader(const std::string& name, const std::string& vertex_file, bool table = true,
                    int texture_px = 0, int png_px = 0) {
        add(name + ".vert", "void main() {}\n", "shaders/" + name + ".vert", "shader_vertex");
        add(name + ".frag", "void main() { /* " + name + " */ }\n", "shaders/" + name + ".frag",
            "shader_fragment");
        nlohmann::json data;  // null
        if (table) {
            add(name + ".brdf.bin", std::string(48, '\2'), "shaders/" + name + ".brdf.bin",
                "shader_data");
            data = name + ".brdf.bin";
        }
        nlohmann::json j = {{"format", "inlight_gles_export"},
                            {"files", {{"vertex", vertex_file},
                                       {"fragment", name + ".frag"},
                                       {"brdf_data", data}}}};
        if (texture_px > 0) {
            const std::string file = name + ".albedo.png";
            image::write_image(src + "/" + file, image::Image(png_px, texture_px, 4, image::ColorSpace::kData));
            request.files.push_back({src + "/" + file, "shaders/" + file, "shader_texture", -1});
            j["files"]["albedo_texture"] = file;
            j["textures"] = {{{"uniform", "u_albedo_texture"}, {"file", file},
                              {"width", texture_px}, {"height", texture_px},
                              {"file_format", "PNG, 8-bit RGBA: the decoded samples are the texel bytes"}}};
        }
        add(name + ".json", j.dump(), "shaders/" + name + ".json", "shader_manifest");
    }
    void add_shader_index(const std::vector<std::string>& names) {
        nlohmann::json variants = nlohmann::json::array();
        for (const auto& n : names) variants.push_back({{"manifest", n + ".json"}});
        add("index.json",
            nlohmann::json({{"format", "inlight_gles_export_index"}, {"variants", variants}}).dump(),
            "shaders/index.json", "shader_index");
    }
    void edit_manifest(const std::function<void(nlohmann::json&)>& edit) const {
        const std::string p = bundle + "/manifest.json";
        nlohmann::json j = nlohmann::json::parse(fs::read_file(p));
        edit(j);
        fs::write_text_atomic(p, j.dump(2));
    }
};

const std::vector<std::pair<int, int>> kStream = {{1, 0}, {0, 0}, {0, 1}, {1, 1}};

TEST(BundleContents, CarriesACompressedBtfInItsStreamOrder) {
    Fabric f("btf");
    f.add_btf(kStream);
    write_bundle(f.bundle, f.request);
    const Manifest m = read_bundle(f.bundle);
    EXPECT_EQ(m.version, kFormatVersion);
    int components = 0;
    for (const FileEntry& e : m.files) {
        // Each file's hash is its source's (core/sha256 on the source, not the bundle's copy).
        const std::string source = f.src + "/" + stdfs::path(e.path).filename().string();
        EXPECT_EQ(e.sha256, sha256_file(source)) << e.path;
        if (e.role != "btf_component") continue;
        ++components;
        const auto [g, c] = kStream.at(static_cast<size_t>(e.stream_index));
        EXPECT_EQ(e.path, str("btf/g00", g, "-c0", c, ".png"));
    }
    EXPECT_EQ(components, 4);
}

TEST(BundleContents, RejectsABtfStreamOrderOtherThanItsManifests) {
    Fabric f("btf_order");
    f.add_btf(kStream);
    write_bundle(f.bundle, f.request);
    // Swap the first two components' positions: the schema still holds (0..n-1 once each).
    f.edit_manifest([](nlohmann::json& j) {
        std::vector<nlohmann::json*> comps;
        for (auto& e : j["files"]) {
            if (e["role"] == "btf_component" && e["stream_index"] < 2) comps.push_back(&e);
        }
        ASSERT_EQ(comps.size(), 2u);
        std::swap((*comps[0])["stream_index"], (*comps[1])["stream_index"]);
    });
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "stream order")) << e;
    // Writing such a bundle fails the same way, and leaves nothing behind.
    Fabric w("btf_order_write");
    w.add_btf(kStream);
    std::swap(w.request.files[5].stream_index, w.request.files[6].stream_index);
    EXPECT_TRUE(contains(error_of([&] { write_bundle(w.bundle, w.request); }), "stream order"));
    EXPECT_FALSE(stdfs::exists(w.bundle));
}

TEST(BundleContents, RejectsABtfWithoutItsMeansWeightsOrManifest) {
    Fabric f("btf_missing");
    f.add_btf(kStream);
    const PackRequest full = f.request;
    const std::pair<std::string, std::string> cases[] = {
        {"btf/g001-mean.png", "groups[1].mean.file: 'btf/g001-mean.png' is not in the bundle"},
        {"btf/weights.bin", "weights.file: 'btf/weights.bin' is not in the bundle"},
        {"btf/btf-pca.json", "files without a btf_manifest"},
    };
    for (const auto& [drop, want] : cases) {
        f.request = full;
        auto& files = f.request.files;
        files.erase(std::remove_if(files.begin(), files.end(),
                                   [&](const PackFile& p) { return p.path == drop; }),
                    files.end());
        const std::string e = error_of([&] { write_bundle(f.bundle, f.request); });
        EXPECT_TRUE(contains(e, want)) << "without " << drop << ": " << e;
    }
}

TEST(BundleContents, CarriesExportedShadersWithTheirManifests) {
    Fabric f("shaders");
    f.add_shader("m-es300-highp", "m-es300-highp.vert");
    f.add_shader("m-es300-mediump", "m-es300-mediump.vert");
    f.add_shader("lambert-es300-highp", "lambert-es300-highp.vert", false);
    f.add_shader_index({"m-es300-highp", "m-es300-mediump", "lambert-es300-highp"});
    write_bundle(f.bundle, f.request);
    const Manifest m = read_bundle(f.bundle);
    // Every file a variant's manifest names is in the bundle, with its source's hash.
    for (const FileEntry& e : m.files) {
        if (e.role != "shader_manifest") continue;
        const auto j = nlohmann::json::parse(fs::read_file(f.bundle + "/" + e.path));
        for (const auto& [key, name] : j["files"].items()) {
            if (name.is_null()) continue;
            const std::string path = "shaders/" + name.get<std::string>();
            const auto it = std::find_if(m.files.begin(), m.files.end(),
                                         [&](const FileEntry& x) { return x.path == path; });
            ASSERT_NE(it, m.files.end()) << key << " " << path;
            EXPECT_EQ(it->sha256, sha256_file(f.src + "/" + name.get<std::string>())) << path;
        }
    }
}

TEST(BundleContents, RejectsAShaderManifestNamingAFileNotInTheBundle) {
    Fabric f("shader_missing");
    f.add_shader("v", "v.vert");
    f.request.files.erase(f.request.files.begin() + 4);  // v.frag
    std::string e = error_of([&] { write_bundle(f.bundle, f.request); });
    EXPECT_TRUE(contains(e, "shaders/v.json: files.fragment: 'shaders/v.frag' is not in the bundle"))
        << e;
    Fabric r("shader_role");
    r.add_shader("v", "v.frag");  // the vertex entry names the fragment shader
    e = error_of([&] { write_bundle(r.bundle, r.request); });
    EXPECT_TRUE(contains(e, "files.vertex: 'shaders/v.frag' has role 'shader_fragment'")) << e;
    Fabric i("shader_index");
    i.add_shader("v", "v.vert");
    i.add_shader_index({"v", "w"});
    e = error_of([&] { write_bundle(i.bundle, i.request); });
    EXPECT_TRUE(contains(e, "variants[1].manifest: 'shaders/w.json' is not in the bundle")) << e;
}

TEST(BundleContents, RejectsATamperedShader) {
    Fabric f("shader_tampered");
    f.add_shader("v", "v.vert");
    write_bundle(f.bundle, f.request);
    const std::string p = f.bundle + "/shaders/v.frag";
    std::string text = fs::read_file(p);
    text[0] = 'V';  // same size, one byte changed
    { std::ofstream(p, std::ios::binary) << text; }
    const std::string e = error_of([&] { read_bundle(f.bundle); });
    EXPECT_TRUE(contains(e, "shaders/v.frag: sha256 mismatch")) << e;
}

TEST(BundleContents, Version1ManifestsAreReadWithoutTheVersion2Roles) {
    Fabric f("v1");
    write_bundle(f.bundle, f.request);
    f.edit_manifest([](nlohmann::json& j) { j["version"] = 1; });
    EXPECT_EQ(read_bundle(f.bundle).version, 1);
    Fabric s("v1_shaders");
    s.add_shader("v", "v.vert");
    write_bundle(s.bundle, s.request);
    s.edit_manifest([](nlohmann::json& j) { j["version"] = 1; });
    const std::string e = error_of([&] { read_bundle(s.bundle); });
    EXPECT_TRUE(contains(e, "role 'shader_data' needs manifest version 2")) << e;
}

TEST(BundleContents, ShaderTexturesAreResolvedAndSizeChecked) {
    Fabric good("shader_texture");
    good.add_shader("v", "v.vert", true, 4, 4);
    write_bundle(good.bundle, good.request);
    int textures = 0;
    for (const FileEntry& e : read_bundle(good.bundle).files) textures += e.role == "shader_texture";
    EXPECT_EQ(textures, 1);
    // One column short of what the manifest binds: the app would upload a wrong-sized texture.
    Fabric narrow("shader_texture_narrow");
    narrow.add_shader("v", "v.vert", true, 4, 3);
    std::string e = error_of([&] { write_bundle(narrow.bundle, narrow.request); });
    EXPECT_TRUE(contains(e, "textures[0].file: 'shaders/v.albedo.png' is 3x4 with 4 8-bit channels; the manifest binds 4x4 8-bit RGBA")) << e;
    // A version-2 manifest may not carry the role version 3 added.
    good.edit_manifest([](nlohmann::json& j) { j["version"] = 2; });
    e = error_of([&] { read_bundle(good.bundle); });
    EXPECT_TRUE(contains(e, "role 'shader_texture' needs manifest version 3")) << e;
}

TEST(BundleContents, CarriesTheBtfGlesShadersBesideTheBtf) {
    Fabric f("btf_gles");
    f.add_btf(kStream);
    f.add_btf_gles();
    write_bundle(f.bundle, f.request);
    const Manifest m = read_bundle(f.bundle);
    EXPECT_EQ(m.version, kFormatVersion);
    // The app finds the export by role; its channel files are the bundle's BTF PNGs.
    const FileEntry* gles = m.find_role("btf_gles_manifest");
    ASSERT_NE(gles, nullptr);
    EXPECT_EQ(gles->path, "btf/btf-gles.json");
    for (const char* role : {"btf_gles_vertex", "btf_gles_fragment", "btf_gles_matrices"})
        EXPECT_NE(m.find_role(role), nullptr) << role;
    // A version-3 manifest may not carry the roles version 4 added.
    f.edit_manifest([](nlohmann::json& j) { j["version"] = 3; });
    EXPECT_TRUE(contains(error_of([&] { read_bundle(f.bundle); }), "needs manifest version 4"));
}

TEST(BundleContents, RejectsBtfGlesShadersNamingWhatTheBundleLacks) {
    // A missing shader: named with the file.
    Fabric f("btf_gles_missing");
    f.add_btf(kStream);
    f.add_btf_gles();
    auto& files = f.request.files;
    files.erase(std::remove_if(files.begin(), files.end(),
                               [](const PackFile& p) { return p.path == "btf/btf-es300-highp.frag"; }),
                files.end());
    std::string e = error_of([&] { write_bundle(f.bundle, f.request); });
    EXPECT_TRUE(contains(e, "btf/btf-gles.json: variants[0].fragment_shader: 'btf/btf-es300-highp.frag' is not in the bundle")) << e;
    EXPECT_FALSE(stdfs::exists(f.bundle));
    const std::pair<std::function<void(nlohmann::json&)>, std::string> cases[] = {
        // A channel naming a component the bundle does not hold.
        {[](nlohmann::json& j) { j["textures"]["groups"][1]["channels"][3]["file"] = "g001-c07.png"; },
         "textures.groups[1].channels[3].file: 'btf/g001-c07.png' is not in the bundle"},
        // A channel naming a bundle file that is no mean or component.
        {[](nlohmann::json& j) { j["textures"]["groups"][0]["channels"][2]["file"] = "weights.bin"; },
         "channels[2].file: 'btf/weights.bin' has role 'btf_weights' in the bundle (expected 'btf_mean' or 'btf_component')"},
        {[](nlohmann::json& j) { j["textures"]["atlas_files"] = true; }, "textures.atlas_files: a bundle ships no atlases"},
        {[](nlohmann::json& j) { j["load"][1]["variant"] = "btf-es100-highp"; },
         "load[1].variant: \"btf-es100-highp\" is not one of its variants"},
        {[](nlohmann::json& j) { j["matrices"]["bytes"] = 95; }, "matrices.bytes: 95, but 'btf/lighting-matrices.bin' holds 96"},
    };
    int n = 0;
    for (const auto& [edit, want] : cases) {
        Fabric c(str("btf_gles_case", n++));
        c.add_btf(kStream);
        c.add_btf_gles(edit);
        e = error_of([&] { write_bundle(c.bundle, c.request); });
        EXPECT_TRUE(contains(e, want)) << e;
    }
    // The shaders without the BTF they draw.
    Fabric alone("btf_gles_alone");
    alone.add_btf_gles();
    e = error_of([&] { write_bundle(alone.bundle, alone.request); });
    EXPECT_TRUE(contains(e, "the BTF's GLES shaders without the BTF")) << e;
}

TEST(Manifest, StreamIndicesRunFromZeroWithoutGaps) {
    Fabric f("stream");
    f.add_btf(kStream);
    auto component = [&](int k) -> PackFile& {
        for (PackFile& p : f.request.files) {
            if (p.role == "btf_component" && p.stream_index == k) return p;
        }
        throw Error("no component");
    };
    component(3).stream_index = 5;
    EXPECT_TRUE(contains(error_of([&] { write_bundle(f.bundle, f.request); }),
                         "stream_index values must be 0..3"));
    component(5).stream_index = -1;
    EXPECT_TRUE(contains(error_of([&] { write_bundle(f.bundle, f.request); }),
                         "stream_index is required"));
}

}  // namespace
}  // namespace inlight::bundle
