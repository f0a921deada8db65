#include "brdf/table.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "image/image.h"

namespace inlight::brdf {
namespace {

constexpr char kMagic[8] = {'I', 'L', 'B', 'R', 'D', 'F', 'S', 'H'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kHeaderBytes = 64;

void put_u32(std::string& out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f32(std::string& out, float f) {
    uint32_t v;
    std::memcpy(&v, &f, 4);
    put_u32(out, v);
}
uint32_t get_u32(const std::string& in, size_t offset) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
        v |= static_cast<uint32_t>(static_cast<unsigned char>(in[offset + i])) << (8 * i);
    }
    return v;
}
float get_f32(const std::string& in, size_t offset) {
    const uint32_t v = get_u32(in, offset);
    float f;
    std::memcpy(&f, &v, 4);
    return f;
}

float mix(float x, float y, float a) { return x * (1.0f - a) + y * a; }  // GLSL mix()

}  // namespace

void Table::resize() {
    coeffs.assign(static_cast<size_t>(channels) * grid.node_count() * coeff_count(), 0.0f);
}

Table first_bands(const Table& table, int bands) {
    if (bands < 1 || bands > table.sh_bands) {
        throw Error(str("BRDF table of ", table.sh_bands, " SH bands: cannot take its first ",
                        bands));
    }
    Table out = table;
    out.sh_bands = bands;
    out.resize();
    const size_t nodes = static_cast<size_t>(table.channels) * table.grid.node_count();
    for (size_t node = 0; node < nodes; ++node) {
        std::copy_n(table.coeffs.begin() + node * table.coeff_count(), out.coeff_count(),
                    out.coeffs.begin() + node * out.coeff_count());
    }
    return out;
}

void lookup(const Table& t, const Eigen::Vector3f& n, int channel, float* out) {
    const GridCoord g = grid_coord(t.grid, n);
    for (int k = 0; k < t.coeff_count(); ++k) {
        const float c00 = t.at(channel, g.r0, g.c0, k), c01 = t.at(channel, g.r0, g.c1, k);
        const float c10 = t.at(channel, g.r1, g.c0, k), c11 = t.at(channel, g.r1, g.c1, k);
        out[k] = mix(mix(c00, c01, g.fc), mix(c10, c11, g.fc), g.fr);
    }
}

void lookup_report_original(const Table& t, const Eigen::Vector3f& n, float* out) {
    const Eigen::Vector2f index = report_original_index(n);
    const int k_count = t.coeff_count();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (!std::isfinite(index.x()) || !std::isfinite(index.y())) {
        for (int k = 0; k < k_count; ++k) out[k] = nan;
        return;
    }
    // ul = (floor x, ceil y), ll = (floor x, floor y), ur = (ceil x, ceil y), lr = (ceil x, floor
    // y)
    const int fx = static_cast<int>(std::floor(index.x())),
              cx = static_cast<int>(std::ceil(index.x()));
    const int fy = static_cast<int>(std::floor(index.y())),
              cy = static_cast<int>(std::ceil(index.y()));
    auto inside = [&](int a, int b) {
        return a >= 0 && a < t.grid.rows && b >= 0 && b < t.grid.cols;
    };
    if (!inside(fx, fy) || !inside(cx, cy)) {
        for (int k = 0; k < k_count; ++k) out[k] = nan;
        return;
    }
    const float hratio = index.x() - std::floor(index.x());
    const float vratio = index.y() - std::floor(index.y());
    for (int k = 0; k < k_count; ++k) {
        out[k] = mix(mix(t.at(0, fx, fy, k), t.at(0, cx, fy, k), hratio),
                     mix(t.at(0, fx, cy, k), t.at(0, cx, cy, k), hratio), vratio);
    }
}

void write_binary(const std::string& path, const Table& t) {
    std::string out(kMagic, 8);
    put_u32(out, kVersion);
    put_u32(out, kHeaderBytes);
    put_u32(out, static_cast<uint32_t>(t.grid.kind));
    put_u32(out, static_cast<uint32_t>(t.grid.rows));
    put_u32(out, static_cast<uint32_t>(t.grid.cols));
    put_u32(out, static_cast<uint32_t>(t.sh_bands));
    put_u32(out, static_cast<uint32_t>(t.coeff_count()));
    put_u32(out, static_cast<uint32_t>(t.channels));
    put_f32(out, static_cast<float>(t.grid.theta_max));
    for (int i = 0; i < 3; ++i) put_f32(out, static_cast<float>(t.view[i]));
    put_u32(out, 0);
    put_u32(out, 0);
    for (float f : t.coeffs) put_f32(out, f);
    fs::write_text_atomic(path, out);
}

Table read_binary(const std::string& path) {
    const std::string in = fs::read_file(path);
    if (in.size() < kHeaderBytes || std::memcmp(in.data(), kMagic, 8) != 0) {
        throw Error(str(path, ": not an inlight BRDF SH table (bad magic)"));
    }
    const uint32_t version = get_u32(in, 8);
    if (version != kVersion) {
        throw Error(str(path, ": unsupported version ", version, " (expected ", kVersion, ")"));
    }
    const uint32_t header = get_u32(in, 12);
    const uint32_t kind = get_u32(in, 16);
    Table t;
    if (kind > 3) throw Error(str(path, ": unknown grid kind ", kind));
    t.grid.kind = static_cast<GridKind>(kind);
    t.grid.rows = static_cast<int>(get_u32(in, 20));
    t.grid.cols = static_cast<int>(get_u32(in, 24));
    t.sh_bands = static_cast<int>(get_u32(in, 28));
    const uint32_t count = get_u32(in, 32);
    t.channels = static_cast<int>(get_u32(in, 36));
    t.grid.theta_max = get_f32(in, 40);
    if (t.grid.kind != GridKind::kThetaPhi) t.grid.theta_max = kPi / 2;
    t.view = Eigen::Vector3d(get_f32(in, 44), get_f32(in, 48), get_f32(in, 52));
    // The grid as parse_grid() makes them: what lookup() and grid_coord() assume.
    const bool square = t.grid.rows == t.grid.cols;
    const bool grid_ok =
        t.grid.kind == GridKind::kReport5x5 ? t.grid.rows == 5 && square
        : t.grid.kind == GridKind::kThetaPhi
            ? t.grid.rows >= 2 && t.grid.cols >= 3 && t.grid.theta_max > 0 && t.grid.theta_max <= kPi
            : t.grid.rows >= 2 && square;
    if (!grid_ok || t.grid.rows > 65536 || t.grid.cols > 65536 || t.sh_bands < 1 ||
        t.sh_bands > 64 || count != static_cast<uint32_t>(t.coeff_count()) ||
        (t.channels != 1 && t.channels != 3) || header < kHeaderBytes) {
        throw Error(str(path, ": inconsistent header (grid ", t.grid.rows, "x", t.grid.cols,
                        ", theta_max ", t.grid.theta_max, ", sh_bands ", t.sh_bands,
                        ", coeff_count ", count, ", channels ", t.channels, ")"));
    }
    if (!t.view.allFinite() || t.view.norm() == 0) {
        throw Error(str(path, ": view direction (", t.view.transpose(), ") is not a direction"));
    }
    // Sizes in 64 bits before anything is allocated: rows x cols x 4096 x 3 exceeds an int.
    const uint64_t values = uint64_t(t.channels) * uint64_t(t.grid.rows) * uint64_t(t.grid.cols) * count;
    const uint64_t need = header + 4 * values;
    if (in.size() != need) {
        throw Error(str(path, ": expected ", need, " bytes, got ", in.size(), " (truncated?)"));
    }
    t.resize();
    for (size_t i = 0; i < t.coeffs.size(); ++i) {
        t.coeffs[i] = get_f32(in, header + 4 * i);
        if (!std::isfinite(t.coeffs[i])) throw Error(str(path, ": coefficient ", i, " is not finite"));
    }
    return t;
}

nlohmann::json to_json(const Table& t, const nlohmann::json& metadata) {
    nlohmann::json j;
    j["format"] = "inlight_brdf_sh_table";
    j["version"] = kVersion;
    j["grid"] = {{"spec", to_string(t.grid)},
                 {"rows", t.grid.rows},
                 {"cols", t.grid.cols},
                 {"theta_max_deg", t.grid.theta_max * 180 / kPi}};
    j["sh_bands"] = t.sh_bands;
    j["coeff_count"] = t.coeff_count();
    j["channels"] = t.channels;
    j["color_space"] = t.channels == 3 ? "linear_srgb" : "achromatic";
    j["view"] = {t.view.x(), t.view.y(), t.view.z()};
    j["frame"] = "device: +z out of the screen toward the viewer, +x right, +y up";
    j["sh_convention"] =
        "real SH without Condon-Shortley phase (R&H 2001), index l*(l+1)+m (lib/sh/sh.h)";
    j["layout"] = "coefficients[((channel * rows + i1) * cols + i2) * coeff_count + k]";
    j["metadata"] = metadata;
    j["coefficients"] = t.coeffs;
    return j;
}

void write_json(const std::string& path, const Table& t, const nlohmann::json& metadata) {
    fs::write_text_atomic(path, dump_finite(to_json(t, metadata), 1, path));
}

Eigen::Vector2i texture_size(const Table& t) {
    const int per_node = (t.coeff_count() + 3) / 4;
    return {t.grid.cols * per_node, t.grid.rows * t.channels};
}

std::vector<float> texture_texels(const Table& t) {
    const Eigen::Vector2i size = texture_size(t);
    const int per_node = (t.coeff_count() + 3) / 4;
    std::vector<float> texels(static_cast<size_t>(size.x()) * size.y() * 4, 0.0f);
    for (int ch = 0; ch < t.channels; ++ch) {
        for (int i1 = 0; i1 < t.grid.rows; ++i1) {
            for (int i2 = 0; i2 < t.grid.cols; ++i2) {
                for (int k = 0; k < t.coeff_count(); ++k) {
                    const int x = i2 * per_node + k / 4, y = ch * t.grid.rows + i1;
                    texels[(static_cast<size_t>(y) * size.x() + x) * 4 + k % 4] =
                        t.at(ch, i1, i2, k);
                }
            }
        }
    }
    return texels;
}

void write_texture_exr(const std::string& path, const Table& t) {
    const Eigen::Vector2i size = texture_size(t);
    image::Image img(size.x(), size.y(), 4, image::ColorSpace::kData);
    img.pixels = texture_texels(t);
    image::WriteOptions options;
    options.exr_half = false;
    image::write_image(path, img, options);
}

}  // namespace inlight::brdf
