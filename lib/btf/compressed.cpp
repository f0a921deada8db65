#include "btf/compressed.h"

#include <zlib.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "btf/quantize.h"
#include "core/json_in.h"
#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "image/color.h"

namespace inlight::btf {

constexpr EnumName<ComponentEncoding> kComponentEncodingNames[] = {
    {ComponentEncoding::kPng8, "png"},
    {ComponentEncoding::kExrHalf, "exr-half"},
    {ComponentEncoding::kExrFloat, "exr-float"},
};

std::string to_string(ComponentEncoding e) { return enum_to_string(kComponentEncodingNames, e); }

ComponentEncoding component_encoding_from_string(const std::string& name) {
    return enum_from_string(kComponentEncodingNames, name, "component format");
}

constexpr EnumName<FitSpace> kFitSpaceNames[] = {
    {FitSpace::kLinear, "linear"},
    {FitSpace::kSrgb, "srgb"},
    {FitSpace::kLab, "lab"},
};

std::string to_string(FitSpace f) { return enum_to_string(kFitSpaceNames, f); }

FitSpace fit_space_from_string(const std::string& name) { return enum_from_string(kFitSpaceNames, name, "fit space"); }

std::string manifest_color_space(FitSpace f) {
    switch (f) {
        case FitSpace::kSrgb: return "srgb_encoded";
        case FitSpace::kLab: return "cielab_d65";
        case FitSpace::kLinear: break;
    }
    return "linear_srgb";
}

constexpr EnumName<WeightsFormat> kWeightsFormatNames[] = {
    {WeightsFormat::kFloat32, "float32"},
    {WeightsFormat::kFloat16, "float16"},
    {WeightsFormat::kUint8, "uint8"},
    {WeightsFormat::kUint8Deflate, "uint8-deflate"},
};

std::string to_string(WeightsFormat f) { return enum_to_string(kWeightsFormatNames, f); }

WeightsFormat weights_format_from_string(const std::string& name) {
    return enum_from_string(kWeightsFormatNames, name, "weights format");
}

namespace {
/// What each weights format stores: bytes per weight and the manifest's dtype, one row per format.
struct WeightsLayout {
    WeightsFormat format;
    int bytes;
    const char* dtype;
};
constexpr WeightsLayout kWeightsLayouts[] = {
    {WeightsFormat::kFloat32, 4, "float32_le"},
    {WeightsFormat::kFloat16, 2, "float16_le"},
    {WeightsFormat::kUint8, 1, "uint8"},
    {WeightsFormat::kUint8Deflate, 1, "uint8_deflate"},
};
const WeightsLayout& layout_of(WeightsFormat f) {
    for (const auto& l : kWeightsLayouts)
        if (l.format == f) return l;
    throw Error(str("weights format ", int(f), ": no such format"));
}
}  // namespace

int bytes_per_weight(WeightsFormat f) { return layout_of(f).bytes; }

std::string weights_dtype(WeightsFormat f) { return layout_of(f).dtype; }

uint64_t encode_weights_column(const float* values, int64_t n, WeightsFormat f, std::string& out, float* decoded,
                               float& scale, float& offset, float min_step) {
    const size_t before = out.size();
    scale = 1;
    offset = 0;
    if (is_uint8(f)) {
        const Quantized8 q = quantize8(values, n, min_step);
        scale = q.scale;
        offset = q.offset;
        if (f == WeightsFormat::kUint8) {
            append_weight_codes(q.codes.data(), n, scale, offset, out, decoded);
        } else {
            std::string raw;
            append_weight_codes(q.codes.data(), n, scale, offset, raw, decoded);
            uLongf size = compressBound(uLong(raw.size()));
            std::string z(size, '\0');
            if (compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                          uLong(raw.size()), Z_BEST_COMPRESSION) != Z_OK)
                throw Error("weights: zlib compress2 failed");
            out.append(z.data(), size);
        }
    } else if (f == WeightsFormat::kFloat16) {
        for (int64_t i = 0; i < n; ++i) {
            const Eigen::half h(values[i]);
            const auto bits = Eigen::numext::bit_cast<uint16_t>(h);
            out.push_back(char(bits & 0xff));
            out.push_back(char(bits >> 8));
            decoded[i] = static_cast<float>(h);
        }
    } else {
        out.append(reinterpret_cast<const char*>(values), size_t(n) * sizeof(float));
        std::copy(values, values + n, decoded);
    }
    return out.size() - before;
}

void append_weight_codes(const uint8_t* codes, int64_t n, float scale, float offset, std::string& out,
                         float* decoded) {
    out.append(reinterpret_cast<const char*>(codes), size_t(n));
    for (int64_t i = 0; i < n; ++i) decoded[i] = offset + scale * codes[i];
}

std::string encode_codes(const uint8_t* codes, int width, int height, float scale, float offset,
                         const std::string& file, StoredImage& meta, float* decoded) {
    const int64_t n = int64_t(width) * height;
    image::Image img(width, height, 1, image::ColorSpace::kData);
    meta.file = file;
    meta.scale = scale * 255.0f;  // stored value = code / 255
    meta.offset = offset;
    for (int64_t i = 0; i < n; ++i) {
        img.pixels[static_cast<size_t>(i)] = codes[i] / 255.0f;
        decoded[i] = offset + scale * codes[i];
    }
    image::WriteOptions wo;
    wo.encode_srgb = false;
    return image::encode_image(file, img, wo);
}

std::string extension_of(ComponentEncoding e) { return e == ComponentEncoding::kPng8 ? "png" : "exr"; }

std::string encode_column(const float* values, int width, int height, ComponentEncoding e,
                          const std::string& file, StoredImage& meta, float* decoded, float min_step) {
    const int64_t n = int64_t(width) * height;
    if (e == ComponentEncoding::kPng8) {
        const Quantized8 q = quantize8(values, n, min_step);
        return encode_codes(q.codes.data(), width, height, q.scale, q.offset, file, meta, decoded);
    }
    image::Image img(width, height, 1, image::ColorSpace::kData);
    image::WriteOptions wo;
    meta.file = file;
    meta.scale = 1;
    meta.offset = 0;
    wo.exr_half = e == ComponentEncoding::kExrHalf;
    for (int64_t i = 0; i < n; ++i) {
        img.pixels[static_cast<size_t>(i)] = values[i];
        decoded[i] = wo.exr_half ? static_cast<float>(Eigen::half(values[i])) : values[i];
    }
    return image::encode_image(file, img, wo);
}

namespace {

Direction direction_of(const nlohmann::json& j, const std::string& where) {
    if (!j.is_array() || j.size() != 2 || !j[0].is_number() || !j[1].is_number())
        throw Error(where + ": a direction must be [theta_deg, phi_deg]");
    return Direction{j[0].get<double>(), j[1].get<double>()};
}

/// An integer in [lo, hi] (get<int>() of 1e300 is undefined behaviour, of 2^32 + 3 it is 3).
int64_t integer(const nlohmann::json& j, int64_t lo, int64_t hi, const std::string& what) {
    if (!j.is_number_integer() || (j.is_number_unsigned() && j.get<uint64_t>() > uint64_t(hi)) ||
        j.get<int64_t>() < lo || j.get<int64_t>() > hi)
        throw Error(str(what, " must be an integer in [", lo, ", ", hi, "]"));
    return j.get<int64_t>();
}

/// A stored column read back: value = offset + scale * stored. Sized by the image read (checked
/// against the manifest's size), so the manifest's width and height allocate nothing.
Eigen::VectorXf read_column(const std::string& dir, const nlohmann::json& meta, const BtfShape& s) {
    const std::string path = dir + "/" + meta.at("file").get<std::string>();
    const image::Image img = image::read_image(path, {false});
    if (img.width != s.width || img.height != s.height || img.channels != 1)
        throw Error(str(path, ": expected a ", s.width, "x", s.height, " one-channel image, got ", img.width,
                        "x", img.height, "x", img.channels));
    const float scale = meta.at("scale").get<float>(), offset = meta.at("offset").get<float>();
    Eigen::VectorXf out(static_cast<Eigen::Index>(img.pixels.size()));
    for (size_t i = 0; i < img.pixels.size(); ++i)
        out[static_cast<Eigen::Index>(i)] = offset + scale * img.pixels[i];
    return out;
}

}  // namespace

std::unique_ptr<CompressedBtf> CompressedBtf::open(const std::string& dir) {
    const std::string manifest_path = dir + "/btf-pca.json";
    std::unique_ptr<CompressedBtf> b(new CompressedBtf());
    b->m_manifest = json_in::read_file(manifest_path);
    const nlohmann::json& m = b->m_manifest;
    try {
        if (m.at("format").get<std::string>() != "inlight-btf-pca" || m.at("version") != 1)
            throw Error(str(manifest_path, ": unknown format or version"));
        BtfShape& s = b->m_shape;
        const std::string space = m.value("color_space", std::string("linear_srgb"));
        if (space == manifest_color_space(FitSpace::kSrgb)) b->m_fit_space = FitSpace::kSrgb;
        else if (space == manifest_color_space(FitSpace::kLab)) b->m_fit_space = FitSpace::kLab;
        else if (space != manifest_color_space(FitSpace::kLinear))
            throw Error(str(manifest_path, ": unknown color_space '", space, "' (linear_srgb, srgb_encoded or cielab_d65)"));
        s.width = static_cast<int>(integer(m.at("width"), 1, 65536, manifest_path + ": width"));
        s.height = static_cast<int>(integer(m.at("height"), 1, 65536, manifest_path + ": height"));
        for (const auto& d : m.at("lights")) s.lights.push_back(direction_of(d, manifest_path));
        for (const auto& d : m.at("views")) s.views.push_back(direction_of(d, manifest_path));
        if (s.width < 1 || s.height < 1 || s.lights.empty() || s.views.empty())
            throw Error(str(manifest_path, ": empty image or direction set"));
        const std::string weights_path = dir + "/" + m.at("weights").at("file").get<std::string>();
        const std::string dtype = m.at("weights").value("dtype", std::string("float32_le"));
        const WeightsLayout* layout = nullptr;
        for (const auto& l : kWeightsLayouts)
            if (dtype == l.dtype) layout = &l;
        if (!layout)
            throw Error(str(manifest_path, ": unknown weights dtype '", dtype, "' (float32_le, float16_le, uint8 or uint8_deflate)"));
        const WeightsFormat wf = layout->format;
        const uint64_t bpw = uint64_t(bytes_per_weight(wf));
        const std::string weights = fs::read_file(weights_path);
        b->m_group_of_view.assign(s.views.size(), -1);
        b->m_index_in_group.assign(s.views.size(), -1);
        for (const auto& gj : m.at("groups")) {
            Group g;
            const int gi = static_cast<int>(b->m_groups.size());
            for (const auto& vj : gj.at("views"))
                g.views.push_back(static_cast<int>(
                    integer(vj, 0, s.n_views() - 1, str(manifest_path, ": group ", gi, ": a view"))));
            for (size_t i = 0; i < g.views.size(); ++i) {
                const int v = g.views[i];
                if (b->m_group_of_view[static_cast<size_t>(v)] >= 0)
                    throw Error(str(manifest_path, ": group ", gi, " names view ", v, " twice"));
                b->m_group_of_view[static_cast<size_t>(v)] = gi;
                b->m_index_in_group[static_cast<size_t>(v)] = static_cast<int>(i);
            }
            const int64_t n = s.group_columns(static_cast<int>(g.views.size()));
            const auto& comps = gj.at("components");
            if (!comps.is_array())
                throw Error(str(manifest_path, ": group ", gi, ": components must be an array"));
            const int c = static_cast<int>(comps.size());
            // V (n x c floats) must fit in weights.bin: checked before the component images are
            // read or anything sized by n or c is allocated, without overflow.
            const uint64_t offset = static_cast<uint64_t>(integer(
                gj.at("weights_offset_bytes"), 0, int64_t(weights.size()), manifest_path + ": weights_offset_bytes"));
            const uint64_t room = weights.size() - offset;
            // uint8_deflate: each column's stream, inflated to exactly n codes (checked).
            std::string inflated;
            if (wf == WeightsFormat::kUint8Deflate) {
                uint64_t at = offset;
                for (int i = 0; i < c; ++i) {
                    const std::string where = str(manifest_path, ": group ", gi, " component ", i, ": v_bytes");
                    const uint64_t zb = uint64_t(integer(comps[static_cast<size_t>(i)].at("v_bytes"), 1,
                                                         int64_t(weights.size() - at), where));
                    const size_t before = inflated.size();
                    inflated.resize(before + size_t(n));
                    uLongf got = uLongf(n);
                    if (uncompress(reinterpret_cast<Bytef*>(inflated.data() + before), &got,
                                   reinterpret_cast<const Bytef*>(weights.data() + at), uLong(zb)) != Z_OK ||
                        got != uLongf(n))
                        throw Error(str(weights_path, ": group ", gi, " component ", i, ": bytes ", at, "..", at + zb,
                                        " are not a zlib stream of ", n, " codes"));
                    at += zb;
                }
            } else if (c > 0 && uint64_t(n) > room / bpw / uint64_t(c)) {
                throw Error(str(weights_path, ": ", weights.size(), " bytes, group ", gi, " needs ", n, " x ", c, " ",
                                dtype, " values from byte ", offset));
            }
            g.mean = read_column(dir, gj.at("mean"), s);
            g.basis.resize(s.pixel_count(), c);
            for (int i = 0; i < c; ++i) g.basis.col(i) = read_column(dir, comps[static_cast<size_t>(i)], s);
            g.weights.resize(n, c);
            const char* w = wf == WeightsFormat::kUint8Deflate ? inflated.data() : weights.data() + offset;
            for (int i = 0; i < c; ++i) {
                float scale = 1, off = 0;
                if (is_uint8(wf)) {
                    const auto& cj = comps[static_cast<size_t>(i)];
                    scale = cj.at("v_scale").get<float>();
                    off = cj.at("v_offset").get<float>();
                }
                for (int64_t r = 0; r < n; ++r, w += bpw) {
                    float v;
                    if (wf == WeightsFormat::kFloat32) {
                        std::memcpy(&v, w, sizeof v);
                    } else if (wf == WeightsFormat::kFloat16) {
                        const uint16_t bits = uint16_t(uint8_t(w[0]) | (uint16_t(uint8_t(w[1])) << 8));
                        v = static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(bits));
                    } else {
                        v = off + scale * float(uint8_t(w[0]));
                    }
                    g.weights(r, i) = v;
                }
            }
            if (!g.weights.allFinite() || !g.basis.allFinite() || !g.mean.allFinite())
                throw Error(str(dir, ": group ", gi, " holds NaN or Inf"));
            b->m_groups.push_back(std::move(g));
        }
        for (size_t v = 0; v < s.views.size(); ++v)
            if (b->m_group_of_view[v] < 0) throw Error(str(manifest_path, ": view ", v, " is in no group"));
        for (const auto& e : m.at("stream")) {
            const std::string where = str(manifest_path, ": a stream entry's ");
            const int g = static_cast<int>(integer(e.at(0), 0, int64_t(b->m_groups.size()) - 1, where + "group"));
            const int c = static_cast<int>(integer(e.at(1), 0, b->components(g) - 1, where + "component"));
            b->m_stream.emplace_back(g, c);
        }
    } catch (const nlohmann::json::exception& e) {
        throw Error(str(manifest_path, ": malformed manifest: ", e.what()));
    }
    return b;
}

image::Image CompressedBtf::decode(int light, int view, const std::vector<int>& per_group) const {
    INLIGHT_CHECK(light >= 0 && light < m_shape.n_lights() && view >= 0 && view < m_shape.n_views());
    const int g = m_group_of_view[static_cast<size_t>(view)];
    const Group& group = m_groups[static_cast<size_t>(g)];
    const int c = per_group[static_cast<size_t>(g)];
    const int64_t base = weights_row(light, view);
    image::Image img(m_shape.width, m_shape.height, 3);
    for (int ch = 0; ch < 3; ++ch) {
        Eigen::VectorXf col = group.mean;
        if (c > 0) col.noalias() += group.basis.leftCols(c) * group.weights.row(base + ch).head(c).transpose();
        if (m_fit_space == FitSpace::kSrgb)
            for (int64_t p = 0; p < m_shape.pixel_count(); ++p) col[p] = image::srgb_decode(std::clamp(col[p], 0.0f, 1.0f));
        for (int64_t p = 0; p < m_shape.pixel_count(); ++p) img.pixels[static_cast<size_t>(p * 3 + ch)] = col[p];
    }
    if (m_fit_space == FitSpace::kLab)
        for (int64_t p = 0; p < m_shape.pixel_count(); ++p) {
            float* x = &img.pixels[static_cast<size_t>(p * 3)];
            const Eigen::Vector3d rgb = image::linear_srgb_from_lab(Eigen::Vector3d(x[0], x[1], x[2])).cwiseMax(0.0).cwiseMin(1.0);
            for (int ch = 0; ch < 3; ++ch) x[ch] = static_cast<float>(rgb[ch]);
        }
    return img;
}

image::Image CompressedBtf::read_image(int light, int view) const {
    std::vector<int> all;
    for (const auto& g : m_groups) all.push_back(static_cast<int>(g.basis.cols()));
    return decode(light, view, all);
}

std::vector<int> CompressedBtf::components_after(int64_t sent) const {
    std::vector<int> per_group(m_groups.size(), 0);
    for (int64_t i = 0; i < std::min<int64_t>(sent, stream_length()); ++i) {
        const auto [g, c] = m_stream[static_cast<size_t>(i)];
        per_group[static_cast<size_t>(g)] = std::max(per_group[static_cast<size_t>(g)], c + 1);
    }
    return per_group;
}

image::Image CompressedBtf::read_image_streamed(int light, int view, int64_t sent) const {
    return decode(light, view, components_after(sent));
}

image::Image CompressedBtf::combine(const std::vector<ImageTerm>& terms) const {
    std::vector<int> all;
    for (const auto& g : m_groups) all.push_back(static_cast<int>(g.basis.cols()));
    return combine_with(terms, all);
}

image::Image CompressedBtf::combine_streamed(const std::vector<ImageTerm>& terms, int64_t sent) const {
    return combine_with(terms, components_after(sent));
}

image::Image CompressedBtf::combine_with(const std::vector<ImageTerm>& terms, const std::vector<int>& per_group) const {
    if (m_fit_space != FitSpace::kLinear) {
        // The sRGB curve (or Lab -> RGB) sits between the sum over components and the image:
        // decode each term's image, then sum in double in the terms' order (BtfSource::combine's arithmetic).
        Eigen::MatrixXd acc = Eigen::MatrixXd::Zero(m_shape.pixel_count(), 3);
        for (const ImageTerm& t : terms) {
            const image::Image x = decode(t.light, t.view, per_group);
            for (int64_t p = 0; p < m_shape.pixel_count(); ++p)
                for (int ch = 0; ch < 3; ++ch) acc(p, ch) += t.weight[ch] * x.pixels[static_cast<size_t>(p * 3 + ch)];
        }
        image::Image img(m_shape.width, m_shape.height, 3);
        for (int64_t p = 0; p < m_shape.pixel_count(); ++p)
            for (int ch = 0; ch < 3; ++ch) img.pixels[static_cast<size_t>(p * 3 + ch)] = static_cast<float>(acc(p, ch));
        return img;
    }
    const size_t ng = m_groups.size();
    // Per group: the mean's weight and the C x 3 component coefficients, summed in term order.
    std::vector<Eigen::Vector3d> mean_w(ng, Eigen::Vector3d::Zero());
    std::vector<Eigen::MatrixXd> coef(ng);
    std::vector<bool> used(ng, false);
    for (size_t g = 0; g < ng; ++g) coef[g] = Eigen::MatrixXd::Zero(per_group[g], 3);
    for (const ImageTerm& t : terms) {
        INLIGHT_CHECK(t.light >= 0 && t.light < m_shape.n_lights() && t.view >= 0 && t.view < m_shape.n_views());
        const auto g = static_cast<size_t>(m_group_of_view[static_cast<size_t>(t.view)]);
        const int64_t base = weights_row(t.light, t.view);
        used[g] = true;
        mean_w[g] += t.weight;
        for (int ch = 0; ch < 3; ++ch)
            coef[g].col(ch) += t.weight[ch] *
                               m_groups[g].weights.row(base + ch).head(per_group[g]).transpose().cast<double>();
    }
    const int64_t np = m_shape.pixel_count();
    Eigen::MatrixXd acc = Eigen::MatrixXd::Zero(np, 3);
    for (size_t g = 0; g < ng; ++g) {
        if (!used[g]) continue;
        const Group& gr = m_groups[g];
        acc += gr.mean.cast<double>() * mean_w[g].transpose();
        if (per_group[g] > 0) acc += gr.basis.leftCols(per_group[g]).cast<double>() * coef[g];
    }
    image::Image img(m_shape.width, m_shape.height, 3);
    for (int64_t p = 0; p < np; ++p)
        for (int ch = 0; ch < 3; ++ch) img.pixels[static_cast<size_t>(p * 3 + ch)] = static_cast<float>(acc(p, ch));
    return img;
}

Eigen::MatrixXd CompressedBtf::lighting_matrix(int view, int channel, const Eigen::MatrixXd& a,
                                              double irradiance_w_m2) const {
    if (m_fit_space != FitSpace::kLinear) {
        throw Error(str("BTF lighting matrix: the model is fitted in ", to_string(m_fit_space),
                        ", whose weighted sums do not fold into its components (linear only)"));
    }
    if (view < 0 || view >= m_shape.n_views() || channel < 0 || channel > 2) {
        throw Error(str("BTF lighting matrix: view ", view, " or channel ", channel, " out of range"));
    }
    if (a.rows() != m_shape.n_lights()) {
        throw Error(str("BTF lighting matrix: A has ", a.rows(), " rows for ", m_shape.n_lights(), " lights"));
    }
    if (!(irradiance_w_m2 > 0) || !std::isfinite(irradiance_w_m2) || !a.allFinite()) {
        throw Error("BTF lighting matrix: A and the irradiance must be finite, the irradiance > 0");
    }
    const auto g = static_cast<size_t>(m_group_of_view[static_cast<size_t>(view)]);
    const Group& gr = m_groups[g];
    const Eigen::Index lights = m_shape.n_lights(), comps = gr.basis.cols();
    // Rows of V for this view and channel, one per light.
    Eigen::MatrixXd v(lights, comps);
    for (Eigen::Index l = 0; l < lights; ++l) {
        v.row(l) = gr.weights.row(weights_row(static_cast<int>(l), view) + channel).cast<double>();
    }
    Eigen::MatrixXd m(1 + comps, a.cols());
    m.row(0) = a.colwise().sum() / irradiance_w_m2;
    m.bottomRows(comps) = v.transpose() * a / irradiance_w_m2;
    return m;
}

}  // namespace inlight::btf
