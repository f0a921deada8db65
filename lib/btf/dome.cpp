#include "btf/dome.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"

namespace inlight::btf {

namespace {

constexpr double kDegree = kPi / 180.0;
/// Two directions closer than this are the same measurement (names carry 1e-3 degrees at most).
constexpr double kDuplicateTolDeg = 1e-6;
/// A direction vector read from a file must be unit length to this (double-precision text).
constexpr double kUnitTol = 1e-6;

/// Parses every whitespace-separated number of a line; false on a token that is not a number.
bool parse_numbers(const std::string& line, std::vector<double>& out) {
    std::istringstream is(line);
    std::string token;
    out.clear();
    while (is >> token) {
        const char* begin = token.c_str();
        char* end = nullptr;
        const double v = std::strtod(begin, &end);
        if (end == begin || *end != '\0') return false;
        out.push_back(v);
    }
    return true;
}

Direction direction_from_numbers(const double* v, int count, const std::string& where) {
    for (int i = 0; i < count; ++i) {
        if (!std::isfinite(v[i])) throw Error(str(where, ": NaN or Inf in a direction"));
    }
    if (count == 2) {
        if (v[0] < 0 || v[0] > 90) {
            throw Error(str(where, ": theta ", v[0], " deg is outside [0, 90]"));
        }
        double phi = std::fmod(v[1], 360.0);
        if (phi < 0) phi += 360.0;
        return {v[0], phi};
    }
    const Eigen::Vector3d vec(v[0], v[1], v[2]);
    if (std::abs(vec.norm() - 1.0) > kUnitTol) {
        throw Error(str(where, ": direction (", v[0], ", ", v[1], ", ", v[2],
                        ") is not unit length (|v| = ", vec.norm(), ")"));
    }
    if (vec.z() < 0) {
        throw Error(str(where, ": direction (", v[0], ", ", v[1], ", ", v[2],
                        ") points below the sample (z < 0)"));
    }
    return Direction::from_vector(vec);
}

/// Calls fn(numbers, where) for every non-blank, non-comment line of a text file.
template <typename Fn>
void for_each_line(const std::string& path, Fn fn) {
    fs::check_input_file(path);
    std::ifstream in(path);
    if (!in) throw Error(str(path, ": cannot open direction file"));
    std::string line;
    std::vector<double> numbers;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        const std::string where = str(path, ":", line_no);
        if (!parse_numbers(line, numbers)) throw Error(str(where, ": not a list of numbers"));
        if (numbers.empty()) continue;
        fn(numbers, where);
    }
}

std::string angle_text(double deg) {
    const double rounded = std::round(deg);
    char buf[32];
    if (std::abs(deg - rounded) < 5e-4) {
        std::snprintf(buf, sizeof buf, "%03d", static_cast<int>(rounded));
    } else {
        std::snprintf(buf, sizeof buf, "%07.3f", deg);
    }
    return buf;
}

}  // namespace

Eigen::Vector3d Direction::vector() const {
    return direction_from_spherical(theta_deg * kDegree, phi_deg * kDegree);
}

Direction Direction::from_vector(const Eigen::Vector3d& v) {
    if (!v.allFinite() || std::abs(v.norm() - 1.0) > kUnitTol || v.z() < -1e-12) {
        throw Error(str("btf direction (", v.x(), ", ", v.y(), ", ", v.z(),
                        ") is not a unit vector on the upper hemisphere"));
    }
    double theta, phi;
    spherical_from_direction(v, theta, phi);
    if (std::hypot(v.x(), v.y()) == 0) phi = 0;
    double phi_deg = phi / kDegree;
    if (phi_deg < 0) phi_deg += 360.0;
    if (phi_deg >= 360.0) phi_deg -= 360.0;
    return {theta / kDegree, phi_deg};
}

double angle_between_deg(const Direction& a, const Direction& b) {
    // atan2(|a x b|, a.b) keeps full precision for tiny and near-pi angles (acos does not).
    const Eigen::Vector3d va = a.vector(), vb = b.vector();
    return std::atan2(va.cross(vb).norm(), va.dot(vb)) / kDegree;
}

const std::vector<Direction>& ubo2003_dome() {
    static const std::vector<Direction> dome = [] {
        const int counts[] = {1, 6, 12, 18, 20, 24};
        std::vector<Direction> d;
        for (int ring = 0; ring < 6; ++ring) {
            for (int k = 0; k < counts[ring]; ++k) {
                d.push_back({15.0 * ring, 360.0 * k / counts[ring]});
            }
        }
        return d;
    }();
    return dome;
}

const std::vector<Direction>& ubo2003_horizon_dome() {
    static const std::vector<Direction> set = [] {
        std::vector<Direction> d = ubo2003_dome();
        for (double theta : kHorizonRingThetasDeg)
            for (int k = 0; k < 24; ++k) d.push_back({theta, 15.0 * k});
        return d;
    }();
    return set;
}

std::vector<Direction> fibonacci_hemisphere(int n) {
    if (n < 2) throw Error(str("fibonacci_hemisphere: ", n, " directions (expected >= 2)"));
    const double golden = (1.0 + std::sqrt(5.0)) / 2.0;
    const double z_span = 1.0 - std::cos(kFibonacciMaxThetaDeg * kDegree);
    std::vector<Direction> d;
    d.reserve(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double z = 1.0 - static_cast<double>(i) / (n - 1) * z_span;
        // i / golden's fraction, so phi keeps full precision for large i.
        const double turns = i / golden;
        // The ends exactly: the pole (theta 0, phi 0) and kFibonacciMaxThetaDeg.
        const double theta_deg = i == 0 ? 0.0 : i == n - 1 ? kFibonacciMaxThetaDeg : std::acos(z) / kDegree;
        d.push_back({theta_deg, 360.0 * (turns - std::floor(turns))});
    }
    return d;
}

std::vector<Direction> named_direction_set(const std::string& name) {
    if (name == "ubo2003") return ubo2003_dome();
    if (name == "ubo2003-horizon") return ubo2003_horizon_dome();
    const std::string prefix = "fibonacci-";
    if (name.rfind(prefix, 0) == 0) {
        const std::string digits = name.substr(prefix.size());
        const bool all_digits = !digits.empty() && digits.size() <= 4 &&
                                digits.find_first_not_of("0123456789") == std::string::npos;
        const int n = all_digits ? std::stoi(digits) : 0;
        if (n >= 16 && n <= 4096) return fibonacci_hemisphere(n);
    }
    throw Error(str("direction set '", name,
                    "': expected ubo2003, ubo2003-horizon or fibonacci-N with N in [16, 4096]"));
}

std::string format_directions(const std::vector<Direction>& dirs, const std::string& comment) {
    std::ostringstream o;
    o.precision(17);
    o << "# " << comment << "\n";
    for (const Direction& d : dirs) o << d.theta_deg << " " << d.phi_deg << "\n";
    return o.str();
}

std::vector<Direction> read_directions(const std::string& path) {
    std::vector<Direction> dirs;
    std::vector<std::string> wheres;
    for_each_line(path, [&](const std::vector<double>& n, const std::string& where) {
        if (n.size() != 2 && n.size() != 3) {
            throw Error(str(where, ": expected `theta_deg phi_deg` or `x y z`, got ", n.size(),
                            " numbers"));
        }
        const Direction d = direction_from_numbers(n.data(), static_cast<int>(n.size()), where);
        if (const auto i = find_direction(dirs, d, kDuplicateTolDeg)) {
            throw Error(str(where, ": direction duplicates the one at ", wheres[*i]));
        }
        dirs.push_back(d);
        wheres.push_back(where);
    });
    if (dirs.empty()) throw Error(str(path, ": no directions"));
    return dirs;
}

std::vector<DirectionPair> read_direction_pairs(const std::string& path) {
    std::vector<DirectionPair> pairs;
    std::vector<std::string> wheres;
    for_each_line(path, [&](const std::vector<double>& n, const std::string& where) {
        if (n.size() != 4 && n.size() != 6) {
            throw Error(str(where,
                            ": expected `theta_l phi_l theta_v phi_v` (degrees) or `lx ly lz vx "
                            "vy vz`, got ",
                            n.size(), " numbers"));
        }
        const int per = static_cast<int>(n.size()) / 2;
        const DirectionPair p{direction_from_numbers(n.data(), per, where),
                              direction_from_numbers(n.data() + per, per, where)};
        for (size_t i = 0; i < pairs.size(); ++i) {
            if (angle_between_deg(pairs[i].light, p.light) <= kDuplicateTolDeg &&
                angle_between_deg(pairs[i].view, p.view) <= kDuplicateTolDeg) {
                throw Error(str(where, ": light/view pair duplicates the one at ", wheres[i]));
            }
        }
        pairs.push_back(p);
        wheres.push_back(where);
    });
    if (pairs.empty()) throw Error(str(path, ": no direction pairs"));
    return pairs;
}

std::string ubo2003_stem(const Direction& light, const Direction& view) {
    return str("tl", angle_text(light.theta_deg), " pl", angle_text(light.phi_deg), " tv",
               angle_text(view.theta_deg), " pv", angle_text(view.phi_deg));
}

std::string ubo2003_view_folder(const Direction& view) {
    return str("tv", angle_text(view.theta_deg), "_pv", angle_text(view.phi_deg));
}

std::optional<DirectionPair> parse_ubo2003_name(const std::string& name) {
    static const std::regex pattern(
        R"(tl(\d+(?:\.\d+)?)\D*?pl(\d+(?:\.\d+)?)\D*?tv(\d+(?:\.\d+)?)\D*?pv(\d+(?:\.\d+)?))",
        std::regex::icase);
    const std::string file = std::filesystem::path(name).filename().string();
    std::smatch m;
    if (!std::regex_search(file, m, pattern)) return std::nullopt;
    auto num = [&](int i) { return std::stod(m[i].str()); };
    return DirectionPair{{num(1), num(2)}, {num(3), num(4)}};
}

std::optional<int> find_direction(const std::vector<Direction>& set, const Direction& d,
                                  double tol_deg) {
    for (size_t i = 0; i < set.size(); ++i) {
        if (angle_between_deg(set[i], d) <= tol_deg) return static_cast<int>(i);
    }
    return std::nullopt;
}

}  // namespace inlight::btf
