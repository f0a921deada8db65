// The SQLite catalogue: what the app's catalogue screen reads, checked with SQLite itself.
#include "bundle/catalog.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>

#include "bundle/bundle.h"
#include "core/fs.h"
#include "core/sha256.h"
#include "image/image.h"
#include "testing/testing.h"

namespace inlight::bundle {
namespace {

namespace stdfs = std::filesystem;

void make_fabric(const std::string& root, const std::string& src, const std::string& id) {
    stdfs::create_directories(src);
    image::write_image(src + "/albedo.png", image::Image(4, 4, 3));
    image::Image thumb(3, 2, 3);
    thumb.at(1, 1, 0) = 0.5f;
    image::write_image(src + "/thumbnail.png", thumb);
    fs::write_text_atomic(src + "/material.toml", "specular = \"lambert\"\n");
    PackRequest r;
    r.kind = Kind::kFabric;
    r.id = id;
    r.name = "Fabric " + id;
    r.properties = {{"sh_bands", 3}};
    r.files = {{src + "/albedo.png", "albedo.png", "albedo", -1},
               {src + "/thumbnail.png", "thumbnail.png", "thumbnail", -1},
               {src + "/material.toml", "material.toml", "material", -1}};
    write_bundle(root + "/fabrics/" + id, r);
}

TEST(Catalog, ListsFabricsWithThumbnailsSizesAndPaths) {
    const std::string dir = testing::temp_dir("catalog_list");
    make_fabric(dir + "/b", dir + "/src", "wool");
    make_fabric(dir + "/b", dir + "/src", "denim");
    const std::string db_path = dir + "/b/catalog.sqlite";
    const auto rows = write_catalog(dir + "/b", db_path);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].id, "denim");  // id order
    EXPECT_EQ(read_catalog(db_path).size(), 2u);

    // Read back with plain SQL, as the app would.
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* s = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db,
                                 "SELECT name, bundle_path, total_bytes, thumbnail_width_px, "
                                 "thumbnail_png, sh_bands FROM fabrics WHERE id = 'wool'",
                                 -1, &s, nullptr),
              SQLITE_OK);
    ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
    EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)), "Fabric wool");
    EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 1)), "fabrics/wool");
    const Manifest m = read_bundle(dir + "/b/fabrics/wool");
    EXPECT_EQ(static_cast<uint64_t>(sqlite3_column_int64(s, 2)), m.total_bytes());
    EXPECT_EQ(sqlite3_column_int(s, 3), 3);
    const std::string blob(static_cast<const char*>(sqlite3_column_blob(s, 4)),
                           sqlite3_column_bytes(s, 4));
    EXPECT_EQ(sha256_hex(blob.data(), blob.size()), m.find_role("thumbnail")->sha256);
    EXPECT_EQ(sqlite3_column_int(s, 5), 3);
    sqlite3_finalize(s);
    sqlite3_close(db);

    // Same bundles, same bytes.
    const std::string first = fs::read_file(db_path);
    write_catalog(dir + "/b", db_path);
    EXPECT_EQ(fs::read_file(db_path), first);
}

TEST(Catalog, RefusesToIndexABrokenBundleAndKeepsTheOldCatalogue) {
    const std::string dir = testing::temp_dir("catalog_broken");
    make_fabric(dir + "/b", dir + "/src", "wool");
    const std::string db_path = dir + "/b/catalog.sqlite";
    write_catalog(dir + "/b", db_path);
    const std::string before = fs::read_file(db_path);
    stdfs::resize_file(dir + "/b/fabrics/wool/albedo.png", 10);
    const std::string e = testing::error_of([&] { write_catalog(dir + "/b", db_path); });
    EXPECT_NE(e.find("albedo.png: truncated"), std::string::npos) << e;
    EXPECT_EQ(fs::read_file(db_path), before);
}

}  // namespace
}  // namespace inlight::bundle
