#include "sh/sh_io.h"

#include <cstdint>
#include <cstring>

#include "core/json_in.h"
#include "core/error.h"
#include "core/fs.h"
#include "sh/sh.h"

namespace inlight::sh {
namespace {
constexpr char kMagic[8] = {'I', 'N', 'L', 'S', 'H', 0, 0, 1};
}

nlohmann::json convention_json() {
    return {{"basis", "real spherical harmonics without the Condon-Shortley phase "
                      "(Ramamoorthi and Hanrahan 2001): Y_1,1 = +0.488603 x"},
            {"index", "k = l*(l+1)+m, l = band, -l <= m <= l"},
            {"frame", "right-handed, +z up; lat-long maps as Blender/Cycles (image centre = +x)"},
            {"units", "radiance coefficients L_lm = integral L(w) Y_lm(w) dw; irradiance "
                      "E(n) = sum A_l L_lm Y_lm(n) = (n,1)^T M (n,1)"},
            {"coefficient_layout", "coefficients[k][channel]"}};
}

nlohmann::json to_json(const CoefficientSet& set) {
    nlohmann::json coeffs = nlohmann::json::array();
    for (int k = 0; k < set.coeffs.rows(); ++k) {
        nlohmann::json row = nlohmann::json::array();
        for (int c = 0; c < set.coeffs.cols(); ++c) row.push_back(set.coeffs(k, c));
        coeffs.push_back(row);
    }
    nlohmann::json doc = {{"format", "inlight.sh_coefficients"},
                          {"version", 1},
                          {"convention", convention_json()},
                          {"sh_bands", set.sh_bands},
                          {"color_space", set.color_space},
                          {"channels", set.channel_names},
                          {"coefficients", coeffs},
                          {"metadata", set.metadata}};
    if (set.sh_bands >= 3) {
        nlohmann::json mats = nlohmann::json::object();
        for (int c = 0; c < set.coeffs.cols(); ++c) {
            Eigen::VectorXd col = set.coeffs.col(c);
            const Eigen::Matrix4d m = irradiance_matrix(col.data());
            nlohmann::json rows = nlohmann::json::array();
            for (int i = 0; i < 4; ++i) rows.push_back({m(i, 0), m(i, 1), m(i, 2), m(i, 3)});
            const std::string name = c < static_cast<int>(set.channel_names.size())
                                         ? set.channel_names[static_cast<size_t>(c)]
                                         : str("c", c);
            mats[name] = rows;
        }
        doc["irradiance_matrices"] = mats;
    }
    return doc;
}

CoefficientSet from_json(const nlohmann::json& doc, const std::string& source) {
    try {
        if (doc.value("format", "") != "inlight.sh_coefficients")
            throw Error("not an inlight.sh_coefficients document");
        CoefficientSet set;
        // An integer first: get<int>() of 1e300 is undefined behaviour, of 2^32 + 3 it is 3.
        const nlohmann::json& bands = doc.at("sh_bands");
        if (!bands.is_number_integer() || bands.get<int64_t>() < 1 || bands.get<int64_t>() > kMaxBands)
            throw Error(str("sh_bands must be an integer in [1, ", kMaxBands, "]"));
        set.sh_bands = static_cast<int>(bands.get<int64_t>());
        set.channel_names = doc.at("channels").get<std::vector<std::string>>();
        set.color_space = doc.value("color_space", "linear_srgb");
        const auto& rows = doc.at("coefficients");
        const int n = count(set.sh_bands), channels = static_cast<int>(set.channel_names.size());
        if (static_cast<int>(rows.size()) != n)
            throw Error(str("expected ", n, " coefficient rows, got ", rows.size()));
        set.coeffs.resize(n, channels);
        for (int k = 0; k < n; ++k) {
            if (static_cast<int>(rows[static_cast<size_t>(k)].size()) != channels)
                throw Error(str("coefficient row ", k, " has ", rows[static_cast<size_t>(k)].size(),
                                " values, expected ", channels));
            for (int c = 0; c < channels; ++c)
                set.coeffs(k, c) = rows[static_cast<size_t>(k)][static_cast<size_t>(c)].get<double>();
        }
        set.metadata = doc.value("metadata", nlohmann::json::object());
        return set;
    } catch (const nlohmann::json::exception& e) {
        throw Error(str(source, ": malformed SH coefficient file: ", e.what()));
    } catch (const Error& e) {
        throw Error(str(source, ": ", e.what()));
    }
}

void write_binary(const std::string& path, const CoefficientSet& set) {
    std::string bytes(kMagic, sizeof(kMagic));
    auto put_u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
    };
    put_u32(static_cast<uint32_t>(set.sh_bands));
    put_u32(static_cast<uint32_t>(set.coeffs.cols()));
    put_u32(0);
    for (int k = 0; k < set.coeffs.rows(); ++k) {
        for (int c = 0; c < set.coeffs.cols(); ++c) {
            const float f = static_cast<float>(set.coeffs(k, c));
            uint32_t u;
            std::memcpy(&u, &f, 4);
            put_u32(u);
        }
    }
    fs::write_text_atomic(path, bytes);
}

CoefficientSet read_binary(const std::string& path) {
    const std::string bytes = fs::read_file(path);
    auto u32 = [&](size_t at) {
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i)
            v |= uint32_t(static_cast<unsigned char>(bytes[at + static_cast<size_t>(i)])) << (8 * i);
        return v;
    };
    if (bytes.size() < 20 || std::memcmp(bytes.data(), kMagic, 8) != 0)
        throw Error(str(path, ": not an inlight SH binary (bad magic)"));
    CoefficientSet set;
    set.sh_bands = static_cast<int>(u32(8));
    const int channels = static_cast<int>(u32(12));
    if (set.sh_bands < 1 || set.sh_bands > kMaxBands || channels < 1 || channels > 16)
        throw Error(str(path, ": bad header (sh_bands ", set.sh_bands, ", channels ", channels, ")"));
    const size_t n = static_cast<size_t>(count(set.sh_bands));
    if (bytes.size() != 20 + 4 * n * static_cast<size_t>(channels))
        throw Error(str(path, ": size ", bytes.size(), " bytes does not match the header"));
    set.coeffs.resize(static_cast<Eigen::Index>(n), channels);
    for (size_t k = 0; k < n; ++k) {
        for (int c = 0; c < channels; ++c) {
            const uint32_t u = u32(20 + 4 * (k * static_cast<size_t>(channels) + static_cast<size_t>(c)));
            float f;
            std::memcpy(&f, &u, 4);
            set.coeffs(static_cast<Eigen::Index>(k), c) = f;
        }
    }
    if (channels != 3) {
        set.channel_names.clear();
        for (int c = 0; c < channels; ++c) set.channel_names.push_back(str("c", c));
    }
    return set;
}

CoefficientSet read_coefficients(const std::string& path) {
    const std::string ext = fs::extension(path);
    if (ext == "bin") return read_binary(path);
    if (ext == "json") {
        const nlohmann::json doc = json_in::read_file(path);
        return from_json(doc, path);
    }
    throw Error(str(path, ": expected a .json or .bin SH coefficient file"));
}

}  // namespace inlight::sh
