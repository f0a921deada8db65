#include "weave/weave.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/check.h"
#include "core/enum_names.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/toml.h"

namespace inlight::weave {

namespace {

constexpr int kMaxPatternRepeat = 64;  ///< threads per pattern repeat, each way
constexpr int kMaxTileThreads = 256;   ///< threads per tile (pattern x colour sequence), each way
constexpr int kPaletteSize = 8;        ///< color_a .. color_h
/// Marks a palette letter that the file does not define.
constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

/// Index in [0, n) of any integer k.
int wrap(long long k, int n) {
    const long long r = k % n;
    return static_cast<int>(r < 0 ? r + n : r);
}

/// Control heights c of the periodic uniform cubic B-spline through heights h at the knots:
/// (c[k-1] + 4 c[k] + c[k+1]) / 6 = h[k] (indices mod n). The circulant matrix has
/// eigenvalues (4 + 2 cos(2 pi m / n)) / 6 >= 1/3, so the system is always solvable.
std::vector<double> interpolating_controls(const std::vector<double>& h) {
    const int n = static_cast<int>(h.size());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int k = 0; k < n; ++k) {
        a(k, k) += 4.0 / 6.0;
        a(k, wrap(k - 1, n)) += 1.0 / 6.0;
        a(k, wrap(k + 1, n)) += 1.0 / 6.0;
    }
    const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(h.data(), n);
    const Eigen::VectorXd c = a.partialPivLu().solve(rhs);
    return std::vector<double>(c.data(), c.data() + n);
}

Eigen::Vector3d colour_of(const WeaveSpec& s, const std::string& sequence,
                          const Eigen::Vector3d& fallback, int thread) {
    if (sequence.empty()) return fallback;
    const char letter =
        sequence[static_cast<size_t>(wrap(thread, static_cast<int>(sequence.size())))];
    return s.palette[static_cast<size_t>(letter - 'a')];
}

}  // namespace

constexpr EnumName<Pattern> kPatternNames[] = {
    {Pattern::kPlain, "plain"},
    {Pattern::kTwill, "twill"},
    {Pattern::kSatin, "satin"},
    {Pattern::kMatrix, "matrix"},
};

std::string to_string(Pattern p) { return enum_to_string(kPatternNames, p); }

Pattern pattern_from_string(const std::string& name) {
    return enum_from_string<Error>(kPatternNames, name, "pattern");
}

Eigen::Vector4d bspline_basis(double u) {
    const double v = 1.0 - u;
    return {v * v * v / 6.0, (3.0 * u * u * u - 6.0 * u * u + 4.0) / 6.0,
            (-3.0 * u * u * u + 3.0 * u * u + 3.0 * u + 1.0) / 6.0, u * u * u / 6.0};
}

Eigen::Vector4d bspline_basis_du(double u) {
    const double v = 1.0 - u;
    return {-0.5 * v * v, 1.5 * u * u - 2.0 * u, -1.5 * u * u + u + 0.5, 0.5 * u * u};
}

Eigen::Vector4d bspline_basis_du2(double u) { return {1.0 - u, 3.0 * u - 2.0, -3.0 * u + 1.0, u}; }

std::vector<char> pattern_matrix(const WeaveSpec& s, int* width, int* height) {
    std::vector<char> m;
    switch (s.pattern) {
        case Pattern::kPlain:
            *width = *height = 2;
            m = {1, 0, 0, 1};
            return m;
        case Pattern::kTwill: {
            const int p = s.twill_over + s.twill_under;
            *width = *height = p;
            m.resize(static_cast<size_t>(p * p));
            for (int j = 0; j < p; ++j) {
                for (int i = 0; i < p; ++i)
                    m[static_cast<size_t>(j * p + i)] = wrap(j - i, p) < s.twill_over;
            }
            return m;
        }
        case Pattern::kSatin: {
            const int h = s.satin_harness;
            *width = *height = h;
            m.assign(static_cast<size_t>(h * h), 1);
            for (int i = 0; i < h; ++i)
                m[static_cast<size_t>(wrap(static_cast<long long>(s.satin_move) * i, h) * h + i)] =
                    0;
            return m;
        }
        case Pattern::kMatrix: {
            std::vector<std::string> rows;
            size_t start = 0;
            while (true) {
                const size_t slash = s.matrix.find('/', start);
                rows.push_back(s.matrix.substr(
                    start, slash == std::string::npos ? std::string::npos : slash - start));
                if (slash == std::string::npos) break;
                start = slash + 1;
            }
            *height = static_cast<int>(rows.size());
            *width = static_cast<int>(rows.front().size());
            m.resize(static_cast<size_t>(*width) * static_cast<size_t>(*height));
            for (int r = 0; r < *height; ++r) {
                const int j = *height - 1 - r;  // the first row drawn is the top weft
                for (int i = 0; i < *width; ++i) {
                    m[static_cast<size_t>(j * *width + i)] =
                        rows[static_cast<size_t>(r)][static_cast<size_t>(i)] == '1';
                }
            }
            return m;
        }
    }
    return m;
}

void validate(const WeaveSpec& s, const std::string& ctx) {
    auto positive = [&ctx](const char* key, double v, double hi) {
        if (!(v > 0 && v <= hi)) throw Error(str(ctx, key, " = ", v, " must be in (0, ", hi, "]"));
    };
    positive("warp_spacing_mm", s.warp_spacing_mm, 100);
    positive("weft_spacing_mm", s.weft_spacing_mm, 100);
    if (!(s.warp_radius_mm > 0 && s.warp_radius_mm <= s.warp_spacing_mm)) {
        throw Error(str(ctx, "warp_radius_mm = ", s.warp_radius_mm,
                        " must be in (0, warp_spacing_mm = ", s.warp_spacing_mm,
                        "] (a yarn may touch but not pass its neighbour's axis)"));
    }
    if (!(s.weft_radius_mm > 0 && s.weft_radius_mm <= s.weft_spacing_mm)) {
        throw Error(str(ctx, "weft_radius_mm = ", s.weft_radius_mm,
                        " must be in (0, weft_spacing_mm = ", s.weft_spacing_mm, "]"));
    }
    if (!(s.crimp_mm < 0 || s.crimp_mm <= 4) || std::isnan(s.crimp_mm)) {
        throw Error(str(ctx, "crimp_mm = ", s.crimp_mm, " must be in [0, 4] (or absent)"));
    }
    switch (s.pattern) {
        case Pattern::kPlain:
            break;
        case Pattern::kTwill:
            if (s.twill_over < 1 || s.twill_under < 1 ||
                s.twill_over + s.twill_under > kMaxPatternRepeat) {
                throw Error(str(ctx, "twill = [", s.twill_over, ", ", s.twill_under,
                                "]: both must be >= 1 with a sum <= ", kMaxPatternRepeat));
            }
            break;
        case Pattern::kSatin: {
            const int h = s.satin_harness, m = s.satin_move;
            if (h < 5 || h > kMaxPatternRepeat || m < 2 || m > h - 2 || std::gcd(h, m) != 1) {
                throw Error(str(ctx, "satin = [", h, ", ", m, "]: the harness H must be in [5, ",
                                kMaxPatternRepeat,
                                "] and the move m in [2, H - 2] with no common factor with H"));
            }
            break;
        }
        case Pattern::kMatrix: {
            if (s.matrix.empty())
                throw Error(str(ctx, "pattern = \"matrix\" needs matrix = \"10/01\""));
            size_t width = std::string::npos, row_len = 0;
            int rows = 1;
            for (char c : s.matrix + "/") {
                if (c == '/') {
                    if (row_len == 0 || (width != std::string::npos && row_len != width)) {
                        throw Error(str(ctx, "matrix \"", s.matrix,
                                        "\": rows must be non-empty and of equal length"));
                    }
                    width = row_len;
                    row_len = 0;
                    ++rows;
                } else if (c == '0' || c == '1') {
                    ++row_len;
                } else {
                    throw Error(
                        str(ctx, "matrix \"", s.matrix, "\": only '0', '1' and '/' allowed"));
                }
            }
            if (static_cast<int>(width) > kMaxPatternRepeat || rows - 1 > kMaxPatternRepeat) {
                throw Error(
                    str(ctx, "matrix: at most ", kMaxPatternRepeat, " x ", kMaxPatternRepeat));
            }
            break;
        }
    }
    auto colours = [&](const char* key, const std::string& seq) {
        if (static_cast<int>(seq.size()) > kMaxTileThreads) {
            throw Error(str(ctx, key, ": at most ", kMaxTileThreads, " letters"));
        }
        for (char c : seq) {
            const int k = c - 'a';
            if (k < 0 || k >= static_cast<int>(s.palette.size()) ||
                std::isnan(s.palette[static_cast<size_t>(k)][0])) {
                throw Error(str(ctx, key, " = \"", seq, "\": letter '", c, "' has no color_", c,
                                " (letters a..", static_cast<char>('a' + kPaletteSize - 1), ")"));
            }
        }
    };
    colours("warp_colors", s.warp_colors);
    colours("weft_colors", s.weft_colors);
    if (s.twist.plies < 0 || s.twist.plies > 12) {
        throw Error(str(ctx, "twist_plies = ", s.twist.plies, " must be in [0, 12]"));
    }
    if (!(s.twist.angle_deg >= 0 && s.twist.angle_deg <= 80)) {
        throw Error(str(ctx, "twist_angle_deg = ", s.twist.angle_deg, " must be in [0, 80]"));
    }
    if (!(s.twist.depth_deg >= 0 && s.twist.depth_deg <= 60)) {
        throw Error(str(ctx, "twist_depth_deg = ", s.twist.depth_deg, " must be in [0, 60]"));
    }
    int pw = 0, ph = 0;
    pattern_matrix(s, &pw, &ph);
    const int nw = std::lcm(pw, std::max<int>(1, static_cast<int>(s.warp_colors.size())));
    const int nf = std::lcm(ph, std::max<int>(1, static_cast<int>(s.weft_colors.size())));
    if (nw > kMaxTileThreads || nf > kMaxTileThreads) {
        throw Error(str(ctx, "the tile would hold ", nw, " x ", nf,
                        " threads (lcm of the pattern repeat and the colour sequence); at most ",
                        kMaxTileThreads));
    }
}

WeaveSpec parse_weave(const std::string& text, const std::string& source) {
    const toml::Document doc = toml::parse(text, source);
    for (const auto& [name, table] : doc.tables) {
        if (name != "material") {
            throw Error(str(source, ":", table.line, ": unknown table [", name,
                            "] (a fabric file has flat keys and a [material] table)"));
        }
    }
    if (!doc.table_arrays.empty()) {
        const auto& [name, list] = *doc.table_arrays.begin();
        throw Error(str(source, ":", list.front().line, ": unknown table array [[", name, "]]"));
    }
    WeaveSpec s;
    const toml::Reader r(doc, doc.root);
    s.name = r.get_string("name", "");
    r.get_string("description", "");
    try {
        s.pattern = pattern_from_string(r.get_string("pattern", "plain"));
    } catch (const Error& e) {
        throw Error(str(r.where("pattern"), e.what()));
    }
    auto int_pair = [&r](const char* key, int* a, int* b) {
        if (!r.has(key)) return;
        const Eigen::VectorXd v = r.get_vector(key, 2, Eigen::Vector2d(*a, *b));
        for (int k = 0; k < 2; ++k) {
            if (v[k] != std::round(v[k]) || std::abs(v[k]) > 1e6) {
                throw Error(str(r.where(key), "expected two integers"));
            }
        }
        *a = static_cast<int>(v[0]);
        *b = static_cast<int>(v[1]);
    };
    int_pair("twill", &s.twill_over, &s.twill_under);
    int_pair("satin", &s.satin_harness, &s.satin_move);
    s.matrix = r.get_string("matrix", "");
    if (!s.matrix.empty() && s.pattern != Pattern::kMatrix) {
        throw Error(str(r.where("matrix"), "only with pattern = \"matrix\""));
    }
    const double spacing = r.get_double("spacing_mm", 0.5);
    s.warp_spacing_mm = r.get_double("warp_spacing_mm", spacing);
    s.weft_spacing_mm = r.get_double("weft_spacing_mm", spacing);
    const double radius = r.get_double("yarn_radius_mm", 0.2);
    s.warp_radius_mm = r.get_double("warp_radius_mm", radius);
    s.weft_radius_mm = r.get_double("weft_radius_mm", radius);
    s.crimp_mm = r.get_double("crimp_mm", -1);
    if (r.has("crimp_mm") && s.crimp_mm < 0) {
        throw Error(str(r.where("crimp_mm"), s.crimp_mm, " must be >= 0"));
    }
    auto colour = [&r](const std::string& key, Eigen::Vector3d& c) {
        c = r.get_vector(key, 3, c, /*allow_scalar=*/true);
        for (int k = 0; k < 3; ++k) r.check_range(key, c[k], 0, 1);
    };
    colour("warp_albedo", s.warp_albedo);
    colour("weft_albedo", s.weft_albedo);
    colour("backing_albedo", s.backing_albedo);
    for (int k = 0; k < kPaletteSize; ++k) {
        const std::string key = str("color_", static_cast<char>('a' + k));
        if (!r.has(key)) continue;
        if (static_cast<int>(s.palette.size()) < k + 1) {
            s.palette.resize(static_cast<size_t>(k + 1), Eigen::Vector3d::Constant(kUndefined));
        }
        Eigen::Vector3d c = Eigen::Vector3d::Constant(0.5);
        colour(key, c);
        s.palette[static_cast<size_t>(k)] = c;
    }
    s.warp_colors = r.get_string("warp_colors", "");
    s.weft_colors = r.get_string("weft_colors", "");
    s.twist.plies = r.get_int("twist_plies", 0);
    s.twist.angle_deg = r.get_double("twist_angle_deg", s.twist.angle_deg);
    s.twist.depth_deg = r.get_double("twist_depth_deg", s.twist.depth_deg);
    r.finish();
    const auto mat = doc.tables.find("material");
    if (mat != doc.tables.end()) {
        const toml::Reader mr(doc, mat->second);
        brdf::read_material_keys(mr, s.material);
        if (mr.has("albedo")) {
            throw Error(
                str(mr.where("albedo"),
                    "the yarns' colours are warp_albedo / weft_albedo / color_* (root keys)"));
        }
        mr.finish();
        brdf::require_specular(mr);
    }
    validate(s, str(source, ": "));
    return s;
}

WeaveSpec load_weave(const std::string& path) {
    std::string text;
    try {
        text = fs::read_file(path);
    } catch (const Error&) {
        throw Error(str(path, ": cannot read fabric file"));
    }
    return parse_weave(text, path);
}

double Yarn::period_mm() const {
    return knot_spacing_mm * static_cast<double>(control_z_mm.size());
}

namespace {
/// The segment holding s: first control index k0 - 1 and the parameter u in [0, 1).
void locate(const Yarn& y, double s, long long* k0, double* u) {
    const double x = s / y.knot_spacing_mm - 0.5;
    const double f = std::floor(x);
    *k0 = static_cast<long long>(f);
    *u = x - f;
}
double eval(const Yarn& y, double s, Eigen::Vector4d (*basis)(double)) {
    long long k0 = 0;
    double u = 0;
    locate(y, s, &k0, &u);
    const Eigen::Vector4d b = basis(u);
    const int n = static_cast<int>(y.control_z_mm.size());
    double z = 0;
    for (int m = 0; m < 4; ++m)
        z += b[m] * y.control_z_mm[static_cast<size_t>(wrap(k0 - 1 + m, n))];
    return z;
}
}  // namespace

double Yarn::z(double s) const { return eval(*this, s, bspline_basis); }
double Yarn::dz_ds(double s) const { return eval(*this, s, bspline_basis_du) / knot_spacing_mm; }

Eigen::Vector3d Yarn::point(double s, const Eigen::Vector2d& shift) const {
    const double h = z(s);
    return set == ThreadSet::kWarp ? Eigen::Vector3d(offset_mm + shift.x(), s + shift.y(), h)
                                   : Eigen::Vector3d(s + shift.x(), offset_mm + shift.y(), h);
}

std::vector<Eigen::Vector4d> Yarn::control_points(double s0, double s1,
                                                  const Eigen::Vector2d& shift,
                                                  double* s_start) const {
    INLIGHT_CHECK_LE(s0, s1);
    const long long first = static_cast<long long>(std::floor(s0 / knot_spacing_mm - 0.5)) - 1;
    const long long last_seg = static_cast<long long>(std::ceil(s1 / knot_spacing_mm - 0.5)) - 2;
    const long long last = std::max(last_seg, first) + 3;
    const int n = static_cast<int>(control_z_mm.size());
    std::vector<Eigen::Vector4d> out;
    out.reserve(static_cast<size_t>(last - first + 1));
    for (long long k = first; k <= last; ++k) {
        const double s = (static_cast<double>(k) + 0.5) * knot_spacing_mm;
        const double h = control_z_mm[static_cast<size_t>(wrap(k, n))];
        if (set == ThreadSet::kWarp) {
            out.emplace_back(offset_mm + shift.x(), s + shift.y(), h, radius_mm);
        } else {
            out.emplace_back(s + shift.x(), offset_mm + shift.y(), h, radius_mm);
        }
    }
    *s_start = (static_cast<double>(first) + 1.5) * knot_spacing_mm;
    return out;
}

bool Weave::over(int i, int j) const {
    return over_matrix[static_cast<size_t>(wrap(j, weft_count) * warp_count +
                                           wrap(i, warp_count))] != 0;
}

Weave build(const WeaveSpec& spec) {
    validate(spec, spec.name.empty() ? "" : str(spec.name, ": "));
    Weave w;
    w.spec = spec;
    int pw = 0, ph = 0;
    const std::vector<char> pattern = pattern_matrix(spec, &pw, &ph);
    w.warp_count = std::lcm(pw, std::max<int>(1, static_cast<int>(spec.warp_colors.size())));
    w.weft_count = std::lcm(ph, std::max<int>(1, static_cast<int>(spec.weft_colors.size())));
    w.over_matrix.resize(static_cast<size_t>(w.warp_count) * static_cast<size_t>(w.weft_count));
    for (int j = 0; j < w.weft_count; ++j) {
        for (int i = 0; i < w.warp_count; ++i) {
            w.over_matrix[static_cast<size_t>(j * w.warp_count + i)] =
                pattern[static_cast<size_t>((j % ph) * pw + (i % pw))];
        }
    }
    w.period_x_mm = w.warp_count * spec.warp_spacing_mm;
    w.period_y_mm = w.weft_count * spec.weft_spacing_mm;
    w.crimp_mm =
        spec.crimp_mm >= 0 ? spec.crimp_mm : 0.5 * (spec.warp_radius_mm + spec.weft_radius_mm);
    // Thread k of `set`: its axis offset, radius, crossings with the other set and colour.
    auto add_yarn = [&](ThreadSet set, int k) {
        const bool warp = set == ThreadSet::kWarp;
        Yarn y;
        y.set = set;
        y.index = k;
        y.offset_mm = (k + 0.5) * (warp ? spec.warp_spacing_mm : spec.weft_spacing_mm);
        y.radius_mm = warp ? spec.warp_radius_mm : spec.weft_radius_mm;
        y.knot_spacing_mm = warp ? spec.weft_spacing_mm : spec.warp_spacing_mm;
        std::vector<double> h(static_cast<size_t>(warp ? w.weft_count : w.warp_count));
        for (size_t c = 0; c < h.size(); ++c) {
            const int other = static_cast<int>(c);
            const bool on_top = warp ? w.over(k, other) : !w.over(other, k);
            h[c] = on_top ? w.crimp_mm : -w.crimp_mm;
        }
        y.control_z_mm = interpolating_controls(h);
        y.albedo = warp ? colour_of(spec, spec.warp_colors, spec.warp_albedo, k)
                        : colour_of(spec, spec.weft_colors, spec.weft_albedo, k);
        w.yarns.push_back(std::move(y));
    };
    for (int i = 0; i < w.warp_count; ++i) add_yarn(ThreadSet::kWarp, i);
    for (int j = 0; j < w.weft_count; ++j) add_yarn(ThreadSet::kWeft, j);
    double r_max = 0, c_lo = 0, c_hi = 0;
    for (const Yarn& y : w.yarns) {
        for (double c : y.control_z_mm) {
            c_lo = std::min(c_lo, c);
            c_hi = std::max(c_hi, c);
        }
        r_max = std::max(r_max, y.radius_mm);
    }
    // The spline lies in the convex hull of its control points.
    w.z_min_mm = c_lo - r_max;
    w.z_max_mm = c_hi + r_max;
    return w;
}

}  // namespace inlight::weave
