// brdf/brdf.h: the analytic BRDF models of inlight (Lambert, the inlight report's Cook-Torrance
// exactly as written, GGX with height-correlated Smith masking, Charlie sheen), their
// importance sampling, and material files.
//
// Papers:
//  - Cook and Torrance 1982, "A Reflectance Model for Computer Graphics" (the V-cavity G, eq. 2
//    of the inlight report section 2.3.1.2).
//  - Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33 (GGX D).
//  - Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
//    eq. 72 (GGX Lambda) and eq. 99 (height-correlated G2 = 1 / (1 + Lambda(o) + Lambda(i))).
//  - Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), listing 1.
//  - Estevez and Kulla 2017, "Production Friendly Microfacet Sheen BRDF" (Charlie D, eq. 2, and
//    the fitted Lambda of table 1 / eq. 3, without the optional terminator softening).
//  - Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), listing 3.
//  - Schlick 1994 (Fresnel approximation).
//
// Frames: every function below works in the LOCAL shading frame, +z = surface normal. `wo`
// (toward the viewer) and `wi` (toward the light) are unit vectors pointing away from the
// surface. Values are BRDFs in 1/sr per linear_srgb channel, WITHOUT the cosine factor.
// Below-horizon directions (wo.z <= 0 or wi.z <= 0) give 0. No function returns NaN or Inf for
// finite unit inputs; roughness is clamped from below to kMinAlpha (see Material).
//
// The report's Cook-Torrance differs from the standard microfacet forms (docs/brdf.md):
//   D_report(c) = r^2 / (pi (c^2 r^2 + 1)^2), c = N.H. Trowbridge-Reitz/GGX is
//   alpha^2 / (pi (c^2 (alpha^2 - 1) + 1)^2); the report drops the "- 1", so D_report
//   DECREASES monotonically from c = 0 to c = 1 (no peak at H = N for any r) and is not
//   normalised: integral of D_report (N.H) dw_h = r^2 / (1 + r^2), not 1 (0.0826 at r = 0.3).
//   G_report is the Cook-Torrance V-cavity term (not a Smith G consistent with D).
#pragma once

#include <Eigen/Core>
#include <string>

namespace inlight::toml {
class Reader;  // core/toml.h
}  // namespace inlight::toml

namespace inlight::brdf {

/// The lobe models.
enum class Model {
    kLambert,             ///< albedo / pi (as a "specular" model: no specular lobe at all)
    kCookTorranceReport,  ///< the inlight report, section 2.3, exactly as written
    kGgx,                 ///< GGX/Trowbridge-Reitz D, height-correlated Smith G2, Schlick F(f0)
    kCharlie,             ///< Estevez-Kulla "Charlie" sheen, tinted by sheen_color
};

/// "lambert" | "cook-torrance-report" | "ggx" | "charlie".
std::string to_string(Model model);
/// Inverse of to_string; throws UsageError listing the accepted names.
Model model_from_string(const std::string& name);

/// Smallest roughness used: alpha (GGX, Charlie) and report_r are clamped up to this, so that
/// D stays finite (GGX D(N) = 1 / (pi alpha^2) = 3.2e7 /sr at the clamp).
inline constexpr double kMinAlpha = 1e-4;

/// Plain material parameters; the renderer overrides albedo (and the normal) per hit.
struct Material {
    /// Diffuse (Lambert) albedo in [0, 1] per linear_srgb channel; 0 for none.
    Eigen::Vector3d albedo{0.5, 0.5, 0.5};
    /// The specular/sheen lobe (the one baked into SH); kLambert = no specular lobe.
    Model specular = Model::kGgx;
    /// GGX Schlick reflectance at normal incidence per channel, [0, 1].
    Eigen::Vector3d f0{0.04, 0.04, 0.04};
    /// GGX: the Trowbridge-Reitz width alpha of Walter et al. (alpha = roughness^2 in the
    /// Disney/UE4 "perceptual roughness" convention); alpha = 1 is a very rough surface.
    /// Charlie: the exponent parameter, D = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), and
    /// the interpolation weight of the fitted Lambda. Range [0, 1]; clamped up to kMinAlpha.
    double alpha = 0.25;
    /// The report's Schlick parameter f in [0, 1] and its roughness r > 0 (clamped up to
    /// kMinAlpha) of D_report above.
    double report_f = 0.04, report_r = 0.3;
    /// Charlie sheen tint per channel, [0, 1].
    Eigen::Vector3d sheen_color{1, 1, 1};
    /// Multiplies the specular/sheen lobe (>= 0).
    double specular_scale = 1.0;
};

/// Reads a flat TOML material file (core/toml.h; no [tables]). Keys (`specular` required, so an
/// empty or truncated file is an error and never a silent default GGX; the others optional,
/// defaults as in Material):
///   specular = "ggx" | "cook-torrance-report" | "charlie" | "lambert"
///   albedo, f0, sheen_color = [r, g, b] or one number for all channels, each in [0, 1]
///   alpha, report_f = number in [0, 1]; report_r = number in (0, 100];
///   specular_scale = number in [0, 1e6]
///   name, description = string (ignored)
/// Throws Error "<file>:<line>: <key>: <what is wrong>" on bad values, wrong types or values out
/// of range, "<file>:<line>: unknown key '<key>' (known: ...)", "<file>: specular: required key
/// is missing ...", "<file>:<line>: tables (...) are not supported in material files",
/// "<file>:<line>:<column>: TOML syntax error: ..." (also for a duplicate key or a binary file),
/// and "<file>: cannot read material file" when it cannot be opened.
Material load_material(const std::string& toml_path);
/// The same from TOML text; `name` is used in error messages.
Material parse_material(const std::string& toml_text, const std::string& name);
/// Reads the material keys above (all but name and description) that the table of `reader` has
/// into `material`, keeping the current values of absent keys; the caller calls
/// reader.finish() after reading its own keys. Scene files use it for inline [material.<name>]
/// overrides, so both accept the same keys and ranges. Throws Error as load_material does.
void read_material_keys(const toml::Reader& reader, Material& material);
/// Throws Error "<where>specular: required key is missing ..." unless the table of `reader` names
/// its lobe: a material file, a fabric's [material] and a scene's [material.<name>] without
/// `file` must say which BRDF they are, rather than bake the default GGX without a word.
void require_specular(const toml::Reader& reader);

/// The material as TOML text that parse_material() reads back to the same values.
std::string to_toml(const Material& material);

/// Diffuse lobe: albedo / pi for wo.z > 0 and wi.z > 0, else 0.
Eigen::Vector3d eval_diffuse(const Material& material, const Eigen::Vector3d& wo,
                             const Eigen::Vector3d& wi);
/// Specular/sheen lobe (model material.specular, times specular_scale); 0 for kLambert.
Eigen::Vector3d eval_specular(const Material& material, const Eigen::Vector3d& wo,
                              const Eigen::Vector3d& wi);
/// eval_diffuse + eval_specular.
Eigen::Vector3d eval(const Material& material, const Eigen::Vector3d& wo,
                     const Eigen::Vector3d& wi);

/// One importance sample of the whole material.
struct Sample {
    Eigen::Vector3d wi = Eigen::Vector3d::Zero();     ///< local frame, unit, wi.z > 0 if valid
    Eigen::Vector3d value = Eigen::Vector3d::Zero();  ///< eval(material, wo, wi), 1/sr
    double pdf = 0;                                   ///< mixture pdf of wi, 1/sr
    bool valid = false;  ///< false if wo.z <= 0 or the sampled direction fell below the horizon
};

/// Probability of choosing the specular lobe in sample() (the rest picks Lambert):
/// w_s = specular_scale * mean over channels of the lobe's Schlick F at cos = wo.z (GGX: f0,
/// report: report_f) or of sheen_color (Charlie); w_d = mean(albedo);
/// p = clamp(w_s / (w_s + w_d), 0.1, 0.9) when both are > 0, else 1 or 0 (0 for wo.z <= 0).
double specular_probability(const Material& material, const Eigen::Vector3d& wo);

/// Importance-samples the material: u_lobe < specular_probability picks the specular lobe,
/// otherwise the diffuse lobe; u in [0, 1)^2 then samples that lobe:
///   Lambert: cosine-weighted hemisphere (Malley);
///   GGX: visible normals (Heitz 2018), wi = reflect(wo, h);
///   report: h with density proportional to D_report(h) (N.H), normalised by r^2 / (1 + r^2):
///           (N.H)^2 = u1 / (1 + r^2 (1 - u1)), phi_h = 2 pi u2; wi = reflect(wo, h);
///   Charlie: h with density D_charlie(h) (N.H), sin(theta_h) = u1^(alpha / (1 + 2 alpha));
/// pdf is the mixture pdf (solid angle) of wi, as pdf() returns; value = eval(wo, wi).
Sample sample(const Material& material, const Eigen::Vector3d& wo, const Eigen::Vector2d& u,
              double u_lobe);
/// Mixture pdf (1/sr) of sample() producing wi; 0 if wo.z <= 0 or wi.z <= 0.
double pdf(const Material& material, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi);

/// The lobe that brdf-sh-bake tabulates: eval_specular, or eval_diffuse when
/// material.specular is kLambert (so that Lambert can be baked for energy tests).
Eigen::Vector3d eval_baked_lobe(const Material& material, const Eigen::Vector3d& wo,
                                const Eigen::Vector3d& wi);
/// Samples only the baked lobe with the rule sample() uses for it (always that lobe, no
/// mixture); pdf = pdf_baked_lobe(wo, wi), value = eval_baked_lobe(wo, wi).
Sample sample_baked_lobe(const Material& material, const Eigen::Vector3d& wo,
                         const Eigen::Vector2d& u);
/// pdf (1/sr) of sample_baked_lobe; 0 below the horizon.
double pdf_baked_lobe(const Material& material, const Eigen::Vector3d& wo,
                      const Eigen::Vector3d& wi);
/// True if the baked lobe has the same value in every channel (then one table channel).
bool baked_lobe_is_achromatic(const Material& material);

// --- The edge-on limit of the baked lobe (docs/brdf.md, "Edge-on normals") ---
// A grid normal exactly perpendicular to the view (wo.z = 0) takes the limit wo.z -> 0+ of the
// lobe with wo's azimuth held. For Lambert, the report's model and GGX, f_r(wo, wi) wi.z has a
// finite limit for every wi.z > 0: the masking of wo falls like wo.z and cancels the
// 1 / (4 wo.z) of the microfacet form. Charlie has none: its fitted Lambda stays finite at
// grazing (exp(L(0))), so f_r cos grows like 1 / (4 wo.z).

/// True for Lambert, the report's model and GGX; false for Charlie.
bool baked_lobe_has_edge_on_limit(const Material& material);
/// lim_{t -> 0+} eval_baked_lobe(material, normalise(wo.x, wo.y, t), wi) for a horizontal unit
/// wo (|wo.z| < 1e-7, treated as 0) and wi.z > 0, 1/sr per channel; with h = normalise(wo +
/// wi) and F = Schlick at wo.h:
///   Lambert: albedo / pi;
///   report: F D_report(h.z) h.z / (2 (wo.h) wi.z)   (G -> 2 (N.H)(N.V) / (V.H));
///   GGX: F D(h.z) / (2 alpha wi.z)                  (G2 -> 2 (N.V) / alpha: Lambda(wo) ~
///        alpha / (2 N.V), Heitz 2014 eq. 72);
/// times specular_scale; 0 if wi.z <= 0. Precondition: baked_lobe_has_edge_on_limit (checked).
Eigen::Vector3d eval_baked_lobe_edge_on(const Material& material, const Eigen::Vector3d& wo,
                                        const Eigen::Vector3d& wi);
/// Samples wi for the edge-on limit, wo as above: GGX by its visible normals at grazing (Heitz
/// 2018, whose density tends to (2 / alpha) D(h) (wo.h)), so pdf(wi) = D(h.z) / (2 alpha);
/// the report's lobe and Lambert as sample_baked_lobe() does (their rules do not depend on wo).
/// value = eval_baked_lobe_edge_on(wo, wi), pdf = pdf_baked_lobe_edge_on(wo, wi).
Sample sample_baked_lobe_edge_on(const Material& material, const Eigen::Vector3d& wo,
                                 const Eigen::Vector2d& u);
/// pdf (1/sr) of sample_baked_lobe_edge_on; 0 if wi.z <= 0 or wo.h <= 0.
double pdf_baked_lobe_edge_on(const Material& material, const Eigen::Vector3d& wo,
                              const Eigen::Vector3d& wi);

// --- Model terms, exposed for tests and docs (all in the local frame, c = cosine to +z) ---

/// The report's D_report(c) = r^2 / (pi (c^2 r^2 + 1)^2), 1/sr; r clamped to kMinAlpha.
double report_d(double r, double cos_nh);
/// The report's G = min(1, 2 (N.H)(N.V)/(V.H), 2 (N.H)(N.L)/(V.H)); 0 if V.H <= 0.
double report_g(const Eigen::Vector3d& wo, const Eigen::Vector3d& wi);
/// GGX D (Walter et al. eq. 33) with alpha clamped to kMinAlpha, 1/sr.
double ggx_d(double alpha, double cos_nh);
/// GGX Smith Lambda(w) for a direction of cosine c > 0 to the normal.
double ggx_lambda(double alpha, double cos_theta);
/// Height-correlated Smith G2 = 1 / (1 + Lambda(wo) + Lambda(wi)); 0 below the horizon.
double ggx_g2(double alpha, const Eigen::Vector3d& wo, const Eigen::Vector3d& wi);
/// Charlie D = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), 1/sr.
double charlie_d(double alpha, double cos_nh);
/// Estevez-Kulla fitted Lambda for the Charlie sheen.
double charlie_lambda(double alpha, double cos_theta);
/// Schlick: f0 + (1 - f0) (1 - cos)^5 with cos clamped to [0, 1].
double schlick(double f0, double cos_theta);

/// Orthonormal frame with +z = n (Duff et al. 2017): columns are t, b, n, so
/// world_from_local * local = world. Precondition: n unit length.
Eigen::Matrix3d world_from_local(const Eigen::Vector3d& n);

}  // namespace inlight::brdf
