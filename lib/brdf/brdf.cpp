#include "brdf/brdf.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/conventions.h"
#include "core/enum_names.h"
#include "core/error.h"

namespace inlight::brdf {
namespace {

// Cosines below this count as below the horizon: keeps 1 / (4 N.V N.L) finite (<= 2.5e17)
// without changing any integral (the excluded band has solid angle ~2e-9 sr).
constexpr double kMinCos = 1e-9;

double clamp_alpha(double alpha) { return std::max(alpha, kMinAlpha); }
double mean(const Eigen::Vector3d& v) { return v.sum() / 3.0; }

bool above(const Eigen::Vector3d& w) { return w.z() >= kMinCos; }

Eigen::Vector3d reflect(const Eigen::Vector3d& wo, const Eigen::Vector3d& h) {
    return 2.0 * wo.dot(h) * h - wo;
}

// Half vector of two upper-hemisphere directions; never zero-length there.
Eigen::Vector3d half_vector(const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    return (wo + wi).normalized();
}

Eigen::Vector3d cosine_hemisphere(const Eigen::Vector2d& u) {
    const double r = std::sqrt(u.x());
    const double phi = 2.0 * kPi * u.y();
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u.x()))};
}

// Direction of polar cosine c and azimuth 2 pi u.
Eigen::Vector3d from_cos(double c, double u) {
    c = std::clamp(c, 0.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = 2.0 * kPi * u;
    return {s * std::cos(phi), s * std::sin(phi), c};
}

// Heitz 2018, listing 1: a visible normal for view wo (upper hemisphere), isotropic alpha.
Eigen::Vector3d sample_ggx_vndf(double alpha, const Eigen::Vector3d& wo, const Eigen::Vector2d& u) {
    const Eigen::Vector3d vh = Eigen::Vector3d(alpha * wo.x(), alpha * wo.y(), wo.z()).normalized();
    const double lensq = vh.x() * vh.x() + vh.y() * vh.y();
    const Eigen::Vector3d t1 = lensq > 0 ? Eigen::Vector3d(-vh.y(), vh.x(), 0) / std::sqrt(lensq)
                                         : Eigen::Vector3d(1, 0, 0);
    const Eigen::Vector3d t2 = vh.cross(t1);
    const double r = std::sqrt(u.x());
    const double phi = 2.0 * kPi * u.y();
    const double p1 = r * std::cos(phi);
    double p2 = r * std::sin(phi);
    const double s = 0.5 * (1.0 + vh.z());
    p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * p2;
    const Eigen::Vector3d nh =
        p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return Eigen::Vector3d(alpha * nh.x(), alpha * nh.y(), std::max(0.0, nh.z())).normalized();
}

bool has_specular(const Material& m) {
    return m.specular != Model::kLambert && m.specular_scale > 0;
}

// pdf of the specular lobe's sampling rule for wi (both above the horizon).
double pdf_specular(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    const Eigen::Vector3d h = half_vector(wo, wi);
    const double wo_h = wo.dot(h);
    if (wo_h <= 0) return 0;
    switch (m.specular) {
        case Model::kGgx: {
            const double a = clamp_alpha(m.alpha);
            const double g1 = 1.0 / (1.0 + ggx_lambda(a, wo.z()));
            return g1 * ggx_d(a, h.z()) / (4.0 * wo.z());
        }
        case Model::kCookTorranceReport: {
            const double r = clamp_alpha(m.report_r);
            const double norm = (1.0 + r * r) / (r * r);  // 1 / integral of D (N.H)
            return report_d(r, h.z()) * h.z() * norm / (4.0 * wo_h);
        }
        case Model::kCharlie:
            return charlie_d(clamp_alpha(m.alpha), h.z()) * h.z() / (4.0 * wo_h);
        case Model::kLambert:
            break;
    }
    return 0;
}

}  // namespace

constexpr EnumName<Model> kModelNames[] = {
    {Model::kLambert, "lambert"},
    {Model::kCookTorranceReport, "cook-torrance-report"},
    {Model::kGgx, "ggx"},
    {Model::kCharlie, "charlie"},
};

std::string to_string(Model model) { return enum_to_string(kModelNames, model); }

Model model_from_string(const std::string& name) {
    return enum_from_string(kModelNames, name, "BRDF model");
}

double schlick(double f0, double cos_theta) {
    const double m = 1.0 - std::clamp(cos_theta, 0.0, 1.0);
    const double m2 = m * m;
    return f0 + (1.0 - f0) * m2 * m2 * m;
}

double report_d(double r, double cos_nh) {
    r = clamp_alpha(r);
    const double r2 = r * r;
    const double t = cos_nh * cos_nh * r2 + 1.0;
    return r2 / (kPi * t * t);
}

double report_g(const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    const Eigen::Vector3d h = half_vector(wo, wi);
    const double vh = wo.dot(h);
    if (vh <= 0) return 0;
    const double nh = h.z();
    return std::min({1.0, 2.0 * nh * wo.z() / vh, 2.0 * nh * wi.z() / vh});
}

double ggx_d(double alpha, double cos_nh) {
    if (cos_nh <= 0) return 0;
    const double a2 = clamp_alpha(alpha) * clamp_alpha(alpha);
    const double t = cos_nh * cos_nh * (a2 - 1.0) + 1.0;
    return a2 / (kPi * t * t);
}

double ggx_lambda(double alpha, double cos_theta) {
    const double c = std::max(cos_theta, kMinCos);
    const double a = clamp_alpha(alpha);
    const double tan2 = std::max(0.0, 1.0 - c * c) / (c * c);
    return 0.5 * (-1.0 + std::sqrt(1.0 + a * a * tan2));
}

double ggx_g2(double alpha, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    if (!above(wo) || !above(wi)) return 0;
    return 1.0 / (1.0 + ggx_lambda(alpha, wo.z()) + ggx_lambda(alpha, wi.z()));
}

double charlie_d(double alpha, double cos_nh) {
    const double inv_a = 1.0 / clamp_alpha(alpha);
    const double sin2 = std::max(0.0, 1.0 - cos_nh * cos_nh);
    return (2.0 + inv_a) * std::pow(sin2, 0.5 * inv_a) / (2.0 * kPi);
}

namespace {
// Estevez and Kulla 2017, table 1: L(x) = a / (1 + b x^c) + d x + e, its coefficients
// interpolated between alpha = 0 and alpha = 1 by t = (1 - alpha)^2.
double charlie_l(double alpha, double x) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    auto lerp = [t](double at1, double at0) { return at0 + t * (at1 - at0); };
    const double a = lerp(25.3245, 21.5473);
    const double b = lerp(3.32435, 3.82987);
    const double c = lerp(0.16801, 0.19823);
    const double d = lerp(-1.27393, -1.97760);
    const double e = lerp(-4.85967, -4.32054);
    return a / (1.0 + b * std::pow(x, c)) + d * x + e;
}
}  // namespace

double charlie_lambda(double alpha, double cos_theta) {
    const double a = std::clamp(alpha, kMinAlpha, 1.0);
    const double c = std::clamp(cos_theta, 0.0, 1.0);
    if (c < 0.5) return std::exp(charlie_l(a, c));
    return std::exp(2.0 * charlie_l(a, 0.5) - charlie_l(a, 1.0 - c));
}

Eigen::Matrix3d world_from_local(const Eigen::Vector3d& n) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    Eigen::Matrix3d m;
    m.col(0) = Eigen::Vector3d(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    m.col(1) = Eigen::Vector3d(b, sign + n.y() * n.y() * a, -n.y());
    m.col(2) = n;
    return m;
}

Eigen::Vector3d eval_diffuse(const Material& m, const Eigen::Vector3d& wo,
                             const Eigen::Vector3d& wi) {
    if (!above(wo) || !above(wi)) return Eigen::Vector3d::Zero();
    return m.albedo * kInvPi;
}

Eigen::Vector3d eval_specular(const Material& m, const Eigen::Vector3d& wo,
                              const Eigen::Vector3d& wi) {
    if (!above(wo) || !above(wi) || !has_specular(m)) return Eigen::Vector3d::Zero();
    const double nv = wo.z(), nl = wi.z();
    const Eigen::Vector3d h = half_vector(wo, wi);
    const double vh = std::clamp(wo.dot(h), 0.0, 1.0);
    switch (m.specular) {
        case Model::kCookTorranceReport: {
            const double f = schlick(m.report_f, vh);
            const double k = f * report_g(wo, wi) * report_d(m.report_r, h.z()) / (4.0 * nv * nl);
            return Eigen::Vector3d::Constant(m.specular_scale * k);
        }
        case Model::kGgx: {
            const double a = clamp_alpha(m.alpha);
            const double dg = ggx_d(a, h.z()) * ggx_g2(a, wo, wi) / (4.0 * nv * nl);
            Eigen::Vector3d out;
            for (int c = 0; c < 3; ++c) out[c] = schlick(m.f0[c], vh) * dg;
            return m.specular_scale * out;
        }
        case Model::kCharlie: {
            const double a = std::clamp(m.alpha, kMinAlpha, 1.0);
            const double g = 1.0 / (1.0 + charlie_lambda(a, nv) + charlie_lambda(a, nl));
            const double k = charlie_d(a, h.z()) * g / (4.0 * nv * nl);
            return m.specular_scale * k * m.sheen_color;
        }
        case Model::kLambert:
            break;
    }
    return Eigen::Vector3d::Zero();
}

Eigen::Vector3d eval(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    return eval_diffuse(m, wo, wi) + eval_specular(m, wo, wi);
}

double specular_probability(const Material& m, const Eigen::Vector3d& wo) {
    if (!above(wo)) return 0;
    double ws = 0;
    if (has_specular(m)) {
        switch (m.specular) {
            case Model::kGgx: {
                Eigen::Vector3d f;
                for (int c = 0; c < 3; ++c) f[c] = schlick(m.f0[c], wo.z());
                ws = m.specular_scale * mean(f);
                break;
            }
            case Model::kCookTorranceReport:
                ws = m.specular_scale * schlick(m.report_f, wo.z());
                break;
            case Model::kCharlie:
                ws = m.specular_scale * mean(m.sheen_color);
                break;
            case Model::kLambert:
                break;
        }
    }
    const double wd = mean(m.albedo);
    if (ws <= 0 && wd <= 0) return has_specular(m) ? 1.0 : 0.0;
    if (ws <= 0) return 0;
    if (wd <= 0) return 1;
    return std::clamp(ws / (ws + wd), 0.1, 0.9);
}

double pdf(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    if (!above(wo) || !above(wi)) return 0;
    const double ps = specular_probability(m, wo);
    double p = (1.0 - ps) * wi.z() * kInvPi;
    if (ps > 0) p += ps * pdf_specular(m, wo, wi);
    return p;
}

namespace {
// A sample in direction wi (unnormalised) with its pdf and value; invalid below the horizon or
// where the pdf is 0.
template <typename Pdf, typename Eval>
Sample finish_sample(Eigen::Vector3d wi, Pdf&& pdf_of, Eval&& eval_of) {
    Sample s;
    if (!above(wi)) return s;
    wi.normalize();
    s.wi = wi;
    s.pdf = pdf_of(wi);
    if (!(s.pdf > 0)) return s;
    s.value = eval_of(wi);
    s.valid = true;
    return s;
}

// Half vector for the specular lobe's sampling rule (upper hemisphere).
Eigen::Vector3d sample_specular_h(const Material& m, const Eigen::Vector3d& wo,
                                  const Eigen::Vector2d& u) {
    switch (m.specular) {
        case Model::kGgx:
            return sample_ggx_vndf(clamp_alpha(m.alpha), wo, u);
        case Model::kCookTorranceReport: {
            const double r2 = clamp_alpha(m.report_r) * clamp_alpha(m.report_r);
            return from_cos(std::sqrt(u.x() / (1.0 + r2 * (1.0 - u.x()))), u.y());
        }
        case Model::kCharlie: {
            const double a = std::clamp(m.alpha, kMinAlpha, 1.0);
            const double sin_h = std::pow(u.x(), a / (1.0 + 2.0 * a));
            return from_cos(std::sqrt(std::max(0.0, 1.0 - sin_h * sin_h)), u.y());
        }
        case Model::kLambert:
            break;
    }
    return Eigen::Vector3d::UnitZ();
}
}  // namespace

Sample sample(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector2d& u,
              double u_lobe) {
    Sample s;
    if (!above(wo)) return s;
    const double ps = specular_probability(m, wo);
    Eigen::Vector3d wi;
    if (u_lobe < ps) {
        const Eigen::Vector3d h = sample_specular_h(m, wo, u);
        if (wo.dot(h) <= 0) return s;
        wi = reflect(wo, h);
    } else {
        wi = cosine_hemisphere(u);
    }
    return finish_sample(
        wi, [&](const Eigen::Vector3d& w) { return pdf(m, wo, w); },
        [&](const Eigen::Vector3d& w) { return eval(m, wo, w); });
}

Eigen::Vector3d eval_baked_lobe(const Material& m, const Eigen::Vector3d& wo,
                                const Eigen::Vector3d& wi) {
    return m.specular == Model::kLambert ? eval_diffuse(m, wo, wi) : eval_specular(m, wo, wi);
}

double pdf_baked_lobe(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi) {
    if (!above(wo) || !above(wi)) return 0;
    if (m.specular == Model::kLambert) return wi.z() * kInvPi;
    return pdf_specular(m, wo, wi);
}

Sample sample_baked_lobe(const Material& m, const Eigen::Vector3d& wo, const Eigen::Vector2d& u) {
    Sample s;
    if (!above(wo)) return s;
    Eigen::Vector3d wi;
    if (m.specular == Model::kLambert) {
        wi = cosine_hemisphere(u);
    } else {
        const Eigen::Vector3d h = sample_specular_h(m, wo, u);
        if (wo.dot(h) <= 0) return s;
        wi = reflect(wo, h);
    }
    return finish_sample(
        wi, [&](const Eigen::Vector3d& w) { return pdf_baked_lobe(m, wo, w); },
        [&](const Eigen::Vector3d& w) { return eval_baked_lobe(m, wo, w); });
}

bool baked_lobe_is_achromatic(const Material& m) {
    auto flat = [](const Eigen::Vector3d& c) { return c[0] == c[1] && c[1] == c[2]; };
    switch (m.specular) {
        case Model::kLambert:
            return flat(m.albedo);
        case Model::kCookTorranceReport:
            return true;
        case Model::kGgx:
            return flat(m.f0);
        case Model::kCharlie:
            return flat(m.sheen_color);
    }
    return false;
}

// --- The edge-on limit ---

bool baked_lobe_has_edge_on_limit(const Material& m) { return m.specular != Model::kCharlie; }

namespace {
// The horizontal view of an edge-on facet (its azimuth); checks the preconditions.
Eigen::Vector3d edge_on_view(const Material& m, const Eigen::Vector3d& wo) {
    INLIGHT_CHECK(baked_lobe_has_edge_on_limit(m))
        << to_string(m.specular) << " has no finite edge-on limit";
    INLIGHT_CHECK(std::abs(wo.z()) < 1e-7) << "wo.z = " << wo.z() << " is not edge-on";
    return Eigen::Vector3d(wo.x(), wo.y(), 0.0).normalized();
}
}  // namespace

Eigen::Vector3d eval_baked_lobe_edge_on(const Material& m, const Eigen::Vector3d& wo_in,
                                        const Eigen::Vector3d& wi) {
    const Eigen::Vector3d wo = edge_on_view(m, wo_in);
    if (!above(wi)) return Eigen::Vector3d::Zero();
    if (m.specular == Model::kLambert) return m.albedo * kInvPi;
    if (!has_specular(m)) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d h = half_vector(wo, wi);
    const double vh = std::clamp(wo.dot(h), 0.0, 1.0);
    if (!(vh > 0)) return Eigen::Vector3d::Zero();
    if (m.specular == Model::kCookTorranceReport) {
        const double k =
            schlick(m.report_f, vh) * report_d(m.report_r, h.z()) * h.z() / (2.0 * vh * wi.z());
        return Eigen::Vector3d::Constant(m.specular_scale * k);
    }
    const double a = clamp_alpha(m.alpha);
    const double d = ggx_d(a, h.z()) / (2.0 * a * wi.z());
    Eigen::Vector3d out;
    for (int c = 0; c < 3; ++c) out[c] = schlick(m.f0[c], vh) * d;
    return m.specular_scale * out;
}

double pdf_baked_lobe_edge_on(const Material& m, const Eigen::Vector3d& wo_in,
                              const Eigen::Vector3d& wi) {
    const Eigen::Vector3d wo = edge_on_view(m, wo_in);
    if (!above(wi)) return 0;
    if (m.specular == Model::kLambert) return wi.z() * kInvPi;
    const Eigen::Vector3d h = half_vector(wo, wi);
    const double vh = wo.dot(h);
    if (!(vh > 0)) return 0;
    if (m.specular == Model::kGgx) {
        const double a = clamp_alpha(m.alpha);
        return ggx_d(a, h.z()) / (2.0 * a);
    }
    return pdf_specular(m, wo, wi);  // the report's rule does not depend on wo.z
}

Sample sample_baked_lobe_edge_on(const Material& m, const Eigen::Vector3d& wo_in,
                                 const Eigen::Vector2d& u) {
    const Eigen::Vector3d wo = edge_on_view(m, wo_in);
    Sample s;
    Eigen::Vector3d wi;
    if (m.specular == Model::kLambert) {
        wi = cosine_hemisphere(u);
    } else {
        const Eigen::Vector3d h = m.specular == Model::kGgx
                                      ? sample_ggx_vndf(clamp_alpha(m.alpha), wo, u)
                                      : sample_specular_h(m, wo, u);
        if (wo.dot(h) <= 0) return s;
        wi = reflect(wo, h);
    }
    return finish_sample(
        wi, [&](const Eigen::Vector3d& w) { return pdf_baked_lobe_edge_on(m, wo, w); },
        [&](const Eigen::Vector3d& w) { return eval_baked_lobe_edge_on(m, wo, w); });
}

}  // namespace inlight::brdf
