#include "btf/dataset.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <regex>

#include "btf/archive.h"
#include "core/check.h"
#include "core/error.h"
#include "core/json_in.h"
#include "core/parallel.h"

namespace inlight::btf {

namespace stdfs = std::filesystem;

namespace {

/// Names carry angles to 3 decimals (rounded to 5e-4 deg each), so a named direction lies
/// within about 7e-4 deg of the set's; 1e-3 deg accepts that and nothing else (the closest
/// two directions of the UBO2003 dome are 14 deg apart).
constexpr double kNameTolDeg = 1e-3;
/// Bytes read from a zip entry to parse its header; the whole entry when that fails.
constexpr uint64_t kHeaderBytes = 1 << 16;
/// Missing images named in an error before "...".
constexpr int kNamedMissing = 8;

bool is_image_extension(const std::string& name) {
    std::string ext = stdfs::path(name).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".exr";
}

std::string angles(const Direction& d) { return str("(", d.theta_deg, ", ", d.phi_deg, ")"); }

/// The view named by a per-view folder ("tv030_pv090"), if the parent folder is one.
std::optional<Direction> folder_view(const std::string& relative) {
    std::string parent = stdfs::path(relative).parent_path().filename().string();
    std::transform(parent.begin(), parent.end(), parent.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (parent.find("tl") != std::string::npos) return std::nullopt;  // not a per-view folder
    static const std::regex pattern(R"(tv(\d+(?:\.\d+)?)\D*?pv(\d+(?:\.\d+)?))");
    std::smatch m;
    if (!std::regex_search(parent, m, pattern)) return std::nullopt;
    return Direction{std::stod(m[1].str()), std::stod(m[2].str())};
}

int locate(const std::vector<Direction>& set, const Direction& d, const std::string& what,
           const std::string& set_name, const std::string& file) {
    if (const auto i = find_direction(set, d, kNameTolDeg)) return *i;
    int nearest = 0;
    double best = 1e9;
    for (size_t i = 0; i < set.size(); ++i) {
        const double a = angle_between_deg(set[i], d);
        if (a < best) best = a, nearest = static_cast<int>(i);
    }
    throw Error(str(file, ": ", what, " direction ", angles(d), " deg is not in the ", what,
                    " set (", set_name, "); the nearest, ", angles(set[nearest]), ", is ", best,
                    " deg away"));
}

std::string describe(const image::ImageInfo& i) {
    return str(i.width, "x", i.height, ", ", i.channels, " channels, ", i.bits_per_channel, "-bit ",
               i.is_float ? "float " : "", i.format);
}

image::Image to_rgb(image::Image img) {
    if (img.channels == 3) return img;
    image::Image rgb(img.width, img.height, 3, img.color_space);
    for (size_t p = 0; p < img.pixel_count(); ++p) {
        for (int c = 0; c < 3; ++c) {
            rgb.pixels[3 * p + c] = img.pixels[p * img.channels + (img.channels >= 3 ? c : 0)];
        }
    }
    return rgb;
}

}  // namespace

void BtfSource::read_group(const std::vector<int>& views, Eigen::MatrixXf& out) const {
    const BtfShape& s = shape();
    for (size_t i = 0; i < views.size(); ++i) {
        INLIGHT_CHECK(views[i] >= 0 && views[i] < s.n_views()) << "view " << views[i];
        for (size_t j = 0; j < i; ++j) INLIGHT_CHECK_NE(views[i], views[j]);
    }
    const int64_t pixels = s.pixel_count();
    out.resize(pixels, s.group_columns(static_cast<int>(views.size())));
    const int64_t images = static_cast<int64_t>(views.size()) * s.n_lights();
    parallel::for_chunks(images, 1, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const int vi = static_cast<int>(i / s.n_lights()),
                      l = static_cast<int>(i % s.n_lights());
            const image::Image img = read_image(l, views[static_cast<size_t>(vi)]);
            INLIGHT_CHECK(img.width == s.width && img.height == s.height && img.channels == 3);
            // One pass over the interleaved pixels into the three colour columns.
            float* red = out.col(i * 3).data();
            float* green = out.col(i * 3 + 1).data();
            float* blue = out.col(i * 3 + 2).data();
            const float* px = img.pixels.data();
            for (int64_t p = 0; p < pixels; ++p, px += 3) {
                red[p] = px[0];
                green[p] = px[1];
                blue[p] = px[2];
            }
        }
    });
}

image::Image BtfSource::combine(const std::vector<ImageTerm>& terms) const {
    const BtfShape& s = shape();
    image::Image out(s.width, s.height, 3, image::ColorSpace::kLinearSrgb);
    std::vector<double> acc(out.pixels.size(), 0.0);
    constexpr size_t kBatch = 16;  // images held at once
    for (size_t t0 = 0; t0 < terms.size(); t0 += kBatch) {
        const size_t n = std::min(kBatch, terms.size() - t0);
        std::vector<image::Image> images(n);
        parallel::for_chunks(static_cast<int64_t>(n), 1, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                const ImageTerm& t = terms[t0 + size_t(i)];
                INLIGHT_CHECK(t.light >= 0 && t.light < s.n_lights() && t.view >= 0 && t.view < s.n_views());
                images[size_t(i)] = read_image(t.light, t.view);
            }
        });
        for (size_t i = 0; i < n; ++i) {
            const Eigen::Vector3d& w = terms[t0 + i].weight;
            const std::vector<float>& px = images[i].pixels;
            INLIGHT_CHECK_EQ(px.size(), acc.size());
            for (size_t k = 0; k < acc.size(); ++k) acc[k] += px[k] * w[int(k % 3)];
        }
    }
    for (size_t k = 0; k < acc.size(); ++k) out.pixels[k] = static_cast<float>(acc[k]);
    return out;
}

struct FolderBtf::Zip {
    std::unique_ptr<ZipArchive> archive;
    std::map<std::string, const ArchiveEntry*> by_name;
};

FolderBtf::~FolderBtf() = default;

std::unique_ptr<FolderBtf> FolderBtf::open(const std::string& path, const OpenOptions& options) {
    std::unique_ptr<FolderBtf> btf(new FolderBtf());
    btf->m_index.root = path;
    btf->m_options = options;
    if (is_zip_path(path)) {
        if (!stdfs::is_regular_file(path)) throw Error(str(path, ": no such zip file"));
        btf->m_zip = std::make_unique<Zip>();
        btf->m_zip->archive = ZipArchive::open(path);
        btf->m_index.is_zip = true;
    } else if (!stdfs::is_directory(path)) {
        throw Error(str(path, ": not a BTF folder or .zip file"));
    }
    btf->build(options);
    return btf;
}

std::unique_ptr<FolderBtf> FolderBtf::open_zip_memory(const void* data, size_t size,
                                                      const std::string& name,
                                                      const OpenOptions& options) {
    std::unique_ptr<FolderBtf> btf(new FolderBtf());
    btf->m_index.root = name;
    btf->m_options = options;
    btf->m_zip = std::make_unique<Zip>();
    btf->m_zip->archive = ZipArchive::open_memory(data, size, name);
    btf->m_index.is_zip = true;
    btf->build(options);
    return btf;
}

std::string FolderBtf::read_bytes(int file, uint64_t max_bytes) const {
    const std::string& name = m_index.files[static_cast<size_t>(file)];
    const ArchiveEntry* e = m_zip->by_name.at(name);
    return m_zip->archive->read(*e, max_bytes);
}

namespace {

/// The direction file a capture folder names in its capture.json under `key` (render
/// capture-btf writes one for a set other than the dome), resolved in the folder; "" when the
/// folder has no capture.json or it names none. Error naming capture.json for a key that is not
/// a plain file name of the folder.
std::string capture_direction_file(const std::string& root, const char* key) {
    const std::string meta_path = (stdfs::path(root) / "capture.json").string();
    std::error_code ec;
    if (!stdfs::is_regular_file(meta_path, ec)) return "";
    const nlohmann::json meta = json_in::read_file(meta_path);
    const auto it = meta.is_object() ? meta.find(key) : meta.end();
    if (it == meta.end()) return "";
    const std::string name = it->is_string() ? it->get<std::string>() : "";
    if (name.empty() || name != stdfs::path(name).filename().string() || name == "." || name == "..")
        throw Error(str(meta_path, ": ", key, " must name a file in the capture folder"));
    return (stdfs::path(root) / name).string();
}

}  // namespace

void FolderBtf::build(const OpenOptions& options) {
    BtfIndex& ix = m_index;
    // A capture folder names its own direction sets when they are not the dome; a given file wins.
    const auto set_file = [&](const std::string& given, const char* key) {
        return !given.empty() || m_zip ? given : capture_direction_file(ix.root, key);
    };
    const std::string light_file = set_file(options.light_directions, "light_directions");
    const std::string view_file = set_file(options.view_directions, "view_directions");
    const std::vector<Direction> lights = light_file.empty() ? ubo2003_dome() : read_directions(light_file);
    const std::vector<Direction> views = view_file.empty() ? ubo2003_dome() : read_directions(view_file);
    const std::string light_set = light_file.empty() ? "UBO2003 dome" : light_file;
    const std::string view_set = view_file.empty() ? "UBO2003 dome" : view_file;
    ix.shape.lights = lights;
    ix.shape.views = views;

    // Every candidate file, in a fixed (sorted) order, with its size.
    std::vector<std::pair<std::string, uint64_t>> names;
    if (m_zip) {
        for (const ArchiveEntry& e : m_zip->archive->entries()) {
            if (e.is_directory) continue;
            names.emplace_back(e.name, e.size);
            m_zip->by_name[e.name] = &e;
        }
    } else {
        for (const auto& e : stdfs::recursive_directory_iterator(ix.root)) {
            if (!e.is_regular_file()) continue;
            // Lexical: the iterator yields root/...; relative() would resolve every component of
            // both paths (13 readlinks per image) and name a symlinked image by its target.
            names.emplace_back(e.path().lexically_relative(ix.root).generic_string(),
                               static_cast<uint64_t>(e.file_size()));
        }
    }
    std::sort(names.begin(), names.end());

    const size_t total = lights.size() * views.size();
    ix.files.assign(total, "");
    std::vector<uint64_t> sizes(total, 0);
    for (const auto& [name, size] : names) {
        const std::string where = str(ix.root, "/", name);
        const auto pair = is_image_extension(name) ? parse_ubo2003_name(name) : std::nullopt;
        if (!pair) {
            ix.ignored.push_back(name);
            continue;
        }
        const int l = locate(lights, pair->light, "light", light_set, where);
        const int v = locate(views, pair->view, "view", view_set, where);
        if (const auto fv = folder_view(name)) {
            if (angle_between_deg(*fv, pair->view) > kNameTolDeg) {
                throw Error(str(where, ": the file names view ", angles(pair->view),
                                " but its folder names view ", angles(*fv)));
            }
        }
        const size_t slot = static_cast<size_t>(v) * lights.size() + static_cast<size_t>(l);
        if (!ix.files[slot].empty()) {
            throw Error(str(where, " and ", ix.root, "/", ix.files[slot],
                            " are the same image: light ", angles(lights[static_cast<size_t>(l)]),
                            ", view ", angles(views[static_cast<size_t>(v)])));
        }
        ix.files[slot] = name;
        sizes[slot] = size;
    }

    int missing = 0;
    std::string named;
    for (size_t slot = 0; slot < total; ++slot) {
        if (!ix.files[slot].empty()) continue;
        if (++missing <= kNamedMissing) {
            named += str(named.empty() ? "" : ", ",
                         ubo2003_stem(lights[slot % lights.size()], views[slot / lights.size()]));
        }
    }
    if (missing == static_cast<int>(total)) {
        throw Error(str(ix.root,
                        ": no BTF images (files named tl.. pl.. tv.. pv.. with .png, .jpg or "
                        ".exr); ",
                        ix.ignored.size(), " other files"));
    }
    if (missing > 0) {
        throw Error(str(ix.root, ": ", missing, " of ", total, " images are missing: ", named,
                        missing > kNamedMissing ? ", ..." : ""));
    }
    for (uint64_t s : sizes) ix.stored_bytes += s;

    // Every header, in parallel; then each compared with the first image's.
    std::vector<image::ImageInfo> infos(total);
    std::vector<std::string> errors(total);
    parallel::for_chunks(static_cast<int64_t>(total), 8, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const size_t slot = static_cast<size_t>(i);
            const std::string where = str(ix.root, "/", ix.files[slot]);
            try {
                if (m_zip) {
                    std::string bytes = read_bytes(static_cast<int>(slot), kHeaderBytes);
                    try {
                        infos[slot] = image::read_info_memory(bytes.data(), bytes.size(), where);
                    } catch (const Error&) {
                        bytes = read_bytes(static_cast<int>(slot), UINT64_MAX);
                        infos[slot] = image::read_info_memory(bytes.data(), bytes.size(), where);
                    }
                } else {
                    infos[slot] = image::read_info(where);
                }
            } catch (const Error& err) {
                errors[slot] = err.what();
            }
        }
    });
    for (const std::string& e : errors) {
        if (!e.empty()) throw Error(e);
    }
    const image::ImageInfo& first = infos[0];
    const std::string first_name = str(ix.root, "/", ix.files[0]);
    if (first.width <= 0 || first.height <= 0 || first.width > options.max_side_px ||
        first.height > options.max_side_px) {
        throw Error(str(first_name, ": image size ", first.width, "x", first.height,
                        " is outside 1..", options.max_side_px));
    }
    if (first.channels != 1 && first.channels != 3 && first.channels != 4) {
        throw Error(str(first_name, ": ", first.channels,
                        " channels (a BTF image has 3, or 1 grey, or 4 with alpha)"));
    }
    for (size_t slot = 1; slot < total; ++slot) {
        const image::ImageInfo& i = infos[slot];
        if (i.width != first.width || i.height != first.height || i.channels != first.channels ||
            i.bits_per_channel != first.bits_per_channel || i.is_float != first.is_float ||
            i.format != first.format) {
            throw Error(str(ix.root, "/", ix.files[slot], ": ", describe(i), ", but ", first_name,
                            " is ", describe(first), " (all images of a BTF must agree)"));
        }
    }
    ix.shape.width = first.width;
    ix.shape.height = first.height;
    ix.format = first.format;
    ix.file_channels = first.channels;
    ix.bits_per_channel = first.bits_per_channel;
    ix.is_float = first.is_float;
}

image::Image FolderBtf::read_image(int light, int view) const {
    const BtfShape& s = m_index.shape;
    INLIGHT_CHECK(light >= 0 && light < s.n_lights() && view >= 0 && view < s.n_views())
        << "light " << light << " view " << view;
    const int slot = view * s.n_lights() + light;
    const std::string where = str(m_index.root, "/", m_index.files[static_cast<size_t>(slot)]);
    image::ReadOptions ro;
    ro.decode_srgb = m_options.decode_srgb;
    image::Image img;
    if (m_zip) {
        const std::string bytes = read_bytes(slot, UINT64_MAX);
        img = image::read_image_memory(bytes.data(), bytes.size(), where, ro);
    } else {
        img = image::read_image(where, ro);
    }
    if (img.width != s.width || img.height != s.height || img.channels != m_index.file_channels) {
        throw Error(str(where, ": ", img.width, "x", img.height, "x", img.channels,
                        " on reading, but its header said ", s.width, "x", s.height, "x",
                        m_index.file_channels));
    }
    img = to_rgb(std::move(img));
    img.color_space = image::ColorSpace::kLinearSrgb;
    return img;
}

void fuzz_read_btf_zip(const uint8_t* data, size_t size, const OpenOptions& options) {
    OpenOptions o = options;
    o.max_side_px = std::min(o.max_side_px, 4096);  // keeps a fuzz run's memory small
    const auto btf = FolderBtf::open_zip_memory(data, size, "fuzz.zip", o);
    for (int v = 0; v < btf->shape().n_views(); ++v) {
        for (int l = 0; l < btf->shape().n_lights(); ++l) btf->read_image(l, v);
    }
}

std::string to_string(ViewGrouping g) { return g == ViewGrouping::kConsecutive ? "consecutive" : "neighbours"; }

std::vector<std::vector<int>> view_groups(const std::vector<Direction>& views, int k, ViewGrouping grouping) {
    INLIGHT_CHECK_GE(k, 1);
    const int n = static_cast<int>(views.size());
    if (grouping == ViewGrouping::kConsecutive) {
        std::vector<std::vector<int>> groups;
        for (int v = 0; v < n; ++v) {
            if (v % k == 0) groups.emplace_back();
            groups.back().push_back(v);
        }
        return groups;
    }
    std::vector<std::vector<double>> dist(static_cast<size_t>(n), std::vector<double>(n, 0.0));
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) dist[a][b] = angle_between_deg(views[a], views[b]);
    // Seeds from the rim inward (largest theta first): the rim's views have the fewest
    // neighbours, so grouping them first leaves no stragglers there.
    std::vector<int> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return views[static_cast<size_t>(a)].theta_deg > views[static_cast<size_t>(b)].theta_deg;
    });
    std::vector<bool> used(static_cast<size_t>(n), false);
    std::vector<std::vector<int>> groups;
    for (int seed : order) {
        if (used[static_cast<size_t>(seed)]) continue;
        std::vector<int> g{seed};
        used[static_cast<size_t>(seed)] = true;
        // Grow by complete linkage: add the view whose farthest member is nearest.
        while (static_cast<int>(g.size()) < k) {
            int best = -1;
            double best_d = 1e9;
            for (int j = 0; j < n; ++j) {
                if (used[static_cast<size_t>(j)]) continue;
                double d = 0;
                for (int m : g) d = std::max(d, dist[j][m]);
                if (d < best_d) best_d = d, best = j;
            }
            if (best < 0) break;
            g.push_back(best);
            used[static_cast<size_t>(best)] = true;
        }
        std::sort(g.begin(), g.end());
        groups.push_back(std::move(g));
    }
    return groups;
}

}  // namespace inlight::btf
