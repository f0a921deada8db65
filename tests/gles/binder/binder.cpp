// tests/gles/binder/binder.cpp: an app's binder written from docs/gles.md and an exported
// manifest alone, without inlight's headers or libraries. It reads <name>.json (or index.json and
// its "load" choice), compiles the variant's sources, binds every attribute, uniform and texture
// from what the manifest gives ("value", "file") or names ("source": the lighting file, the
// scene's camera and patches), draws into an RGBA32F target, applies the manifest's 8-bit
// encoding (output.encoding_8bit) and writes the codes as a binary PPM; with --reference it
// compares them with another PPM (the harness's image of the same draw) within one code.
//
//   inlight_gles_binder MANIFEST|index.json --lighting FILE -o OUT.ppm [--reference REF.ppm]
//                       [--load-choice I] [--quad N]
// --quad N: for a manifest without "scene" (brdf-sh-bake's), draw quad_vertices() into N x N.
// Exit 0 = drawn (and within one code of the reference); 1 = a missing or bad manifest field
// (named), a GL failure, or more than one code off; 2 = usage.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <png.h>
#include <csetjmp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using nlohmann::json;

namespace {

struct Fail : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string g_manifest;  // for messages

/// The field at a dotted path, or Fail naming it.
const json& need(const json& j, const std::string& path) {
    const json* at = &j;
    std::stringstream in(path);
    std::string key;
    while (std::getline(in, key, '.')) {
        if (!at->is_object() || !at->contains(key) || (*at)[key].is_null()) {
            throw Fail(g_manifest + ": missing field '" + path + "'");
        }
        at = &(*at)[key];
    }
    return *at;
}

std::string read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Fail(path + ": cannot read");
    return std::string(std::istreambuf_iterator<char>(f), {});
}

/// An 8-bit RGBA PNG's samples as stored (no gamma, colour or alpha step: libpng's plain read
/// with no transforms), as the manifest's file_format "PNG, 8-bit RGBA" asks.
std::string read_png_rgba8(const std::string& path) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Fail(path + ": cannot read");
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    std::string out;
    bool ok = false;
    if (info && !setjmp(png_jmpbuf(png))) {
        png_init_io(png, f);
        png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
        const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
        if (png_get_bit_depth(png, info) == 8 && png_get_color_type(png, info) == PNG_COLOR_TYPE_RGBA) {
            png_bytepp rows = png_get_rows(png, info);
            for (png_uint_32 y = 0; y < h; ++y) out.append(reinterpret_cast<const char*>(rows[y]), w * 4);
            ok = true;
        }
    }
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(f);
    if (!ok) throw Fail(path + ": not an 8-bit RGBA PNG");
    return out;
}

json read_json(const std::string& path) {
    try {
        return json::parse(read_bytes(path));
    } catch (const json::exception& e) {
        throw Fail(path + ": not JSON: " + e.what());
    }
}

std::string folder_of(const std::string& path) {
    const size_t slash = path.rfind('/');
    return slash == std::string::npos ? "." : path.substr(0, slash);
}

// ---- Lighting: the file the manifest's "source" names (docs/formats.md) ----

struct Lighting {
    std::vector<float> sh;  ///< count x 3, zero-padded as the manifest's padding rule says
    json lights = json::array();
};

Lighting read_lighting(const std::string& path, int count) {
    const json doc = read_json(path);
    if (!doc.contains("coefficients")) throw Fail(path + ": no \"coefficients\"");
    const json& c = doc["coefficients"];
    Lighting l;
    l.sh.assign(static_cast<size_t>(count) * 3, 0.0f);  // rows the file lacks: (0, 0, 0)
    for (int k = 0; k < count && k < static_cast<int>(c.size()); ++k) {
        for (int ch = 0; ch < 3; ++ch) {
            const double v = c[k].at(ch).get<double>();
            if (!std::isfinite(v)) throw Fail(path + ": coefficient not finite");
            l.sh[k * 3 + ch] = static_cast<float>(v);
        }
    }
    if (doc.contains("lights")) l.lights = doc["lights"];
    return l;
}

/// float32 in 4 bytes as the manifest's packing states: byte 0 = exponent + 127 (0 = zero),
/// bytes 1-3 = the 24-bit mantissa with its leading 1 replaced by the sign.
void pack_float(float v, uint8_t* out) {
    int exponent = 0;
    const double m = std::frexp(std::fabs(static_cast<double>(v)), &exponent);  // [0.5, 1)
    if (v == 0.0f || exponent + 127 < 1) {
        std::memset(out, 0, 4);
        return;
    }
    const auto bits = static_cast<uint32_t>(std::ldexp(m, 24));
    out[0] = static_cast<uint8_t>(exponent + 127);
    out[1] = static_cast<uint8_t>(((bits >> 16) & 0x7f) | (v < 0 ? 0x80 : 0));
    out[2] = static_cast<uint8_t>(bits >> 8);
    out[3] = static_cast<uint8_t>(bits);
}

/// u_sh_texture's texels from the coefficients, as its "packing" states.
std::string pack_lighting(const json& t, const std::vector<float>& sh, int count) {
    const std::string type = need(t, "type");
    const int width = need(t, "width"), height = need(t, "height");
    if (width != count) throw Fail(g_manifest + ": u_sh_texture width " + std::to_string(width) + " != coefficients");
    if (type == "FLOAT") {
        std::vector<float> texels(static_cast<size_t>(width) * height * 4, 0.0f);
        for (int k = 0; k < count; ++k) std::copy_n(&sh[k * 3], 3, &texels[k * 4]);
        return std::string(reinterpret_cast<const char*>(texels.data()), texels.size() * 4);
    }
    if (height != 4) throw Fail(g_manifest + ": u_sh_texture RGBA8 packing needs 4 rows");
    std::string bytes(static_cast<size_t>(width) * 16, '\0');
    auto texel = [&](int k, int row) { return reinterpret_cast<uint8_t*>(&bytes[(row * width + k) * 4]); };
    for (int k = 0; k < count; ++k) {
        const float* L = &sh[k * 3];
        const float offset = std::min({L[0], L[1], L[2]});
        const float scale = std::max({L[0], L[1], L[2]}) - offset;
        pack_float(scale, texel(k, 2));
        pack_float(offset, texel(k, 3));
        for (int c = 0; c < 3; ++c) {
            long q = scale > 0 ? std::lround((L[c] - offset) / scale * 65535.0) : 0;
            q = std::clamp(q, 0L, 65535L);
            texel(k, 0)[c] = static_cast<uint8_t>(q >> 8);
            texel(k, 1)[c] = static_cast<uint8_t>(q & 0xff);
        }
    }
    return bytes;
}

/// u_light_direction (vec4 per light) and u_light_irradiance (vec3) from the lighting file's
/// lights, by the manifest's from_lighting_file rules.
std::vector<float> light_values(const json& lights, bool direction, int count, const std::string& path) {
    if (static_cast<int>(lights.size()) != count) {
        throw Fail(path + ": " + std::to_string(lights.size()) + " lights, the variant shades " + std::to_string(count));
    }
    std::vector<float> out;
    for (const json& l : lights) {
        const double alpha = l.at("angular_radius_deg").get<double>() * M_PI / 180.0;
        if (direction) {
            double d[3], n = 0;
            for (int i = 0; i < 3; ++i) {
                d[i] = l.at("direction").at(i).get<double>();
                n += d[i] * d[i];
            }
            for (double v : d) out.push_back(static_cast<float>(v / std::sqrt(n)));
            out.push_back(alpha < 1e-4 ? 0.0f : static_cast<float>(std::sin(alpha)));
        } else {
            for (int i = 0; i < 3; ++i) {
                out.push_back(static_cast<float>(l.at("flux").at(i).get<double>() * (1 + std::cos(alpha)) / 2));
            }
        }
    }
    return out;
}

// ---- GL ----

struct Gl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    explicit Gl(int major) {
        auto platform = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (platform) display = platform(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display == EGL_NO_DISPLAY) display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr)) throw Fail("EGL: no display");
        eglBindAPI(EGL_OPENGL_ES_API);
        const EGLint want[] = {EGL_RENDERABLE_TYPE, major == 3 ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT,
                               EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
        EGLConfig config;
        EGLint n = 0;
        if (!eglChooseConfig(display, want, &config, 1, &n) || n < 1) throw Fail("EGL: no OpenGL ES config");
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_NONE};
        context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
        if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
            throw Fail("EGL: no surfaceless OpenGL ES " + std::to_string(major) + " context");
        }
    }
    ~Gl() {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        eglTerminate(display);
    }
};

void check_gl(const std::string& what) {
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
        throw Fail("GL error " + std::to_string(e) + " " + what);
    }
}

GLuint compile(GLenum stage, const std::string& path) {
    const std::string text = read_bytes(path);
    const char* src = text.c_str();
    const GLuint s = glCreateShader(stage);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetShaderInfoLog(s, sizeof(log), nullptr, log);
        throw Fail(path + " does not compile: " + log);
    }
    return s;
}

GLenum gl_enum(const std::string& name, const std::string& field) {
    static const std::map<std::string, GLenum> names = {
        {"RGBA", GL_RGBA}, {"RGBA8", GL_RGBA8}, {"RGBA32F", GL_RGBA32F}, {"SRGB8_ALPHA8", GL_SRGB8_ALPHA8},
        {"UNSIGNED_BYTE", GL_UNSIGNED_BYTE}, {"FLOAT", GL_FLOAT}, {"NEAREST", GL_NEAREST},
        {"LINEAR", GL_LINEAR}, {"CLAMP_TO_EDGE", GL_CLAMP_TO_EDGE}, {"REPEAT", GL_REPEAT}};
    const auto it = names.find(name);
    if (it == names.end()) throw Fail(g_manifest + ": " + field + " '" + name + "' is not a GL name this binder knows");
    return it->second;
}

/// A uniform's floats from "value": numbers, or {"file": ...} (float32 little-endian).
std::vector<float> value_floats(const json& u, const std::string& dir) {
    const json& v = u["value"];
    std::vector<float> out;
    if (v.is_object()) {
        const std::string bytes = read_bytes(dir + "/" + need(v, "file").get<std::string>());
        out.resize(bytes.size() / 4);
        std::memcpy(out.data(), bytes.data(), out.size() * 4);
        return out;
    }
    if (v.is_number()) return {v.get<float>()};
    for (const json& x : v) out.push_back(x.get<float>());
    return out;
}

struct Options {
    std::string manifest, lighting, output, reference;
    int load_choice = 0;
    int quad_px = 0;  ///< --quad N: no scene in the manifest; draw quad_vertices() N x N
};

/// The test quad for a manifest without a scene (brdf-sh-bake's exports): the clip square
/// [-1, 1]^2 at z = 0 (u_clip_from_object = identity), two triangles, a_normal = normalize(0.6 x,
/// 0.6 y, 1) at its corners, a_tangent = (1, 0, 0), a_uv = ((x + 1) / 2, (1 - y) / 2).
std::vector<float> quad_vertices() {
    std::vector<float> out;
    for (const auto& [x, y] : {std::pair{-1, 1}, {1, 1}, {1, -1}, {-1, 1}, {1, -1}, {-1, -1}}) {
        const double n = std::sqrt(0.36 * x * x + 0.36 * y * y + 1);
        const float v[11] = {float(x), float(y), 0, float(0.6 * x / n), float(0.6 * y / n), float(1 / n), 1, 0, 0,
                             float((x + 1) / 2.0), float((1 - y) / 2.0)};
        out.insert(out.end(), v, v + 11);
    }
    return out;
}

int components(const std::string& type) {
    if (type == "float") return 1;
    if (type == "vec2") return 2;
    if (type == "vec3") return 3;
    if (type == "vec4") return 4;
    if (type == "mat4") return 16;
    throw Fail(g_manifest + ": uniform type '" + type + "'");
}

int run(const Options& o) {
    g_manifest = o.manifest;
    json m = read_json(o.manifest);
    std::string dir = folder_of(o.manifest);
    if (m.value("format", "") == "inlight_gles_export_index") {  // the variant "load" names
        const json& load = need(m, "load");
        if (load.empty()) throw Fail(o.manifest + ": \"load\" is empty");
        const json& choice = load.begin().value().at(o.load_choice);
        g_manifest = dir + "/" + need(choice, "variant").get<std::string>() + ".json";
        m = read_json(g_manifest);
    }
    const bool es3 = need(m, "variant.glsl_version") == "300 es";
    json quad_scene;  // without a scene: the stated quad, o.quad_px square
    if (o.quad_px > 0) {
        std::vector<float> identity(16, 0.0f);
        for (int i = 0; i < 4; ++i) identity[i * 5] = 1.0f;
        quad_scene = {{"camera", {{"width_px", o.quad_px}, {"height_px", o.quad_px}}},
                      {"clip_from_object", identity}};
        json patch = {{"vertices", json::array()}};
        const std::vector<float> q = quad_vertices();
        for (size_t i = 0; i < q.size(); i += 11) {
            patch["vertices"].push_back(std::vector<float>(q.begin() + i, q.begin() + i + 11));
        }
        quad_scene["patches"] = json::array({patch});
    }
    const json& scene = o.quad_px > 0 ? quad_scene : need(m, "scene");
    const int width = need(scene, "camera.width_px"), height = need(scene, "camera.height_px");
    Gl gl(es3 ? 3 : 2);

    const GLuint program = glCreateProgram();
    glAttachShader(program, compile(GL_VERTEX_SHADER, dir + "/" + need(m, "files.vertex").get<std::string>()));
    glAttachShader(program, compile(GL_FRAGMENT_SHADER, dir + "/" + need(m, "files.fragment").get<std::string>()));
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) throw Fail(g_manifest + ": the program does not link");
    glUseProgram(program);

    // Uniforms: "value" as given, else "source" resolved.
    auto lighting = [&](int k_count) {
        if (o.lighting.empty()) throw Fail(g_manifest + ": a uniform's source is the lighting file: give --lighting");
        return read_lighting(o.lighting, k_count);
    };
    for (const json& u : need(m, "uniforms")) {
        const std::string name = need(u, "name");
        const std::string type = need(u, "type");
        const int n = need(u, "count");
        std::vector<float> v;
        if (u.contains("value") && !u["value"].is_null()) {
            v = value_floats(u, dir);
        } else if (u.contains("source")) {
            const std::string from = need(u, "source.from");
            if (from == "camera") {
                v = need(scene, "clip_from_object").get<std::vector<float>>();
            } else if (from == "lighting_file.coefficients") {
                v = lighting(need(u, "source.count")).sh;
            } else if (from == "lighting_file.lights") {
                v = light_values(lighting(1).lights, name == "u_light_direction", n, o.lighting);
            } else {
                throw Fail(g_manifest + ": uniform " + name + ": unknown source '" + from + "'");
            }
        } else {
            throw Fail(g_manifest + ": uniform " + name + " has neither 'value' nor 'source'");
        }
        const int c = components(type);
        if (static_cast<int>(v.size()) < n * c) {
            throw Fail(g_manifest + ": uniform " + name + " needs " + std::to_string(n * c) + " floats, has " +
                       std::to_string(v.size()));
        }
        const GLint loc = glGetUniformLocation(program, name.c_str());
        if (loc < 0) throw Fail(g_manifest + ": uniform " + name + " is not in the program");
        if (c == 16) glUniformMatrix4fv(loc, n, GL_FALSE, v.data());
        if (c == 4) glUniform4fv(loc, n, v.data());
        if (c == 3) glUniform3fv(loc, n, v.data());
        if (c == 2) glUniform2fv(loc, n, v.data());
        if (c == 1) glUniform1fv(loc, n, v.data());
    }

    // What the variant requires of the context (gl_limits_needed.requires: an extension name or
    // GL_FRAGMENT_PRECISION_HIGH, then its explanation).
    const std::string extensions = reinterpret_cast<const char*>(glGetString(GL_EXTENSIONS));
    for (const json& r : need(m, "gl_limits_needed.requires")) {
        const std::string what = r.get<std::string>(), name = what.substr(0, what.find(' '));
        bool offered = false;
        if (name == "GL_FRAGMENT_PRECISION_HIGH") {
            GLint range[2] = {0, 0}, precision = 0;
            glGetShaderPrecisionFormat(GL_FRAGMENT_SHADER, GL_HIGH_FLOAT, range, &precision);
            offered = precision > 0;
        } else {
            offered = (" " + extensions + " ").find(" " + name + " ") != std::string::npos;
        }
        if (!offered) throw Fail(g_manifest + ": the context lacks " + name + ", which the variant requires");
    }

    // Textures: "file" or "source".
    for (const json& t : need(m, "textures")) {
        const std::string name = need(t, "uniform");
        const int unit = need(t, "unit"), w = need(t, "width"), h = need(t, "height");
        const GLenum type = gl_enum(need(t, "type"), name + ".type");
        std::string data;
        if (t.contains("file") && !t["file"].is_null()) {
            const std::string file = dir + "/" + t["file"].get<std::string>();
            const std::string format = need(t, "file_format");
            data = format.rfind("PNG", 0) == 0 ? read_png_rgba8(file) : read_bytes(file);
        } else if (t.contains("source")) {
            const int k_count = need(t, "source.count");
            data = pack_lighting(t, lighting(k_count).sh, k_count);
        } else {
            throw Fail(g_manifest + ": texture " + name + " has neither 'file' nor 'source'");
        }
        if (t.contains("mip")) {  // a mip atlas: the shader reads its levels; they must lie inside it
            for (const json& level : need(t, "mip.levels")) {
                const int x = need(level, "x"), y = need(level, "y"), lw = need(level, "width"), lh = need(level, "height");
                if (x < 0 || y < 0 || lw < 1 || lh < 1 || x + lw > w || y + lh > h) {
                    throw Fail(g_manifest + ": texture " + name + ": mip level " + level.dump() + " is not inside its " +
                               std::to_string(w) + "x" + std::to_string(h) + " texels");
                }
            }
        }
        const size_t want = static_cast<size_t>(w) * h * 4 * (type == GL_FLOAT ? 4 : 1);
        if (data.size() != want) {
            throw Fail(g_manifest + ": texture " + name + " has " + std::to_string(data.size()) + " bytes, " +
                       std::to_string(w) + "x" + std::to_string(h) + " needs " + std::to_string(want));
        }
        GLuint tex;
        glGenTextures(1, &tex);
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, tex);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(gl_enum(need(t, "internal_format"), name + ".internal_format")),
                     w, h, 0, gl_enum(need(t, "format"), name + ".format"), type, data.data());
        const GLint filter = static_cast<GLint>(gl_enum(need(t, "filter"), name + ".filter"));
        const GLint wrap = static_cast<GLint>(gl_enum(need(t, "wrap"), name + ".wrap"));
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
        glUniform1i(glGetUniformLocation(program, name.c_str()), unit);
    }
    check_gl("binding " + g_manifest);

    // Geometry: the scene's patches, 11 floats per vertex (scene.patch_vertex).
    std::vector<float> vertices;
    for (const json& p : need(scene, "patches")) {
        for (const json& v : need(p, "vertices")) {
            for (const json& x : v) vertices.push_back(x.get<float>());
        }
    }
    if (vertices.empty()) throw Fail(g_manifest + ": scene.patches has no vertices");
    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * 4), vertices.data(), GL_STATIC_DRAW);
    const std::map<std::string, std::pair<int, int>> layout = {
        {"a_position", {3, 0}}, {"a_normal", {3, 3}}, {"a_tangent", {3, 6}}, {"a_uv", {2, 9}}};
    for (const json& a : need(m, "attributes")) {
        const std::string name = need(a, "name");
        const auto it = layout.find(name);
        if (it == layout.end()) throw Fail(g_manifest + ": attribute " + name + " has no data in scene.patch_vertex");
        const GLint loc = glGetAttribLocation(program, name.c_str());
        if (loc < 0) throw Fail(g_manifest + ": attribute " + name + " is not in the program");
        glEnableVertexAttribArray(static_cast<GLuint>(loc));
        glVertexAttribPointer(static_cast<GLuint>(loc), it->second.first, GL_FLOAT, GL_FALSE, 11 * 4,
                              reinterpret_cast<const void*>(static_cast<size_t>(it->second.second) * 4));
    }

    // RGBA32F target (output.framebuffer), depth test as a scene draw.
    GLuint fbo, target, depth;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenTextures(1, &target);
    glActiveTexture(GL_TEXTURE0 + 15);
    glBindTexture(GL_TEXTURE_2D, target);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT16, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw Fail("an RGBA32F framebuffer is not complete on this driver");
    }
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / 11));
    std::vector<float> px(static_cast<size_t>(width) * height * 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, px.data());
    check_gl("drawing " + g_manifest);

    // output.encoding_8bit: auto exposure over the drawn pixels, clamp, sRGB OETF, round.
    need(m, "output.encoding_8bit.steps");
    if (need(m, "output.encoding_8bit.exposure.default") != "auto") throw Fail(g_manifest + ": exposure default is not 'auto'");
    double sum = 0;
    long drawn = 0;
    for (size_t i = 0; i < px.size(); i += 4) {
        if (px[i + 3] <= 0) continue;
        sum += 0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2];
        ++drawn;
    }
    const double mean = drawn > 0 ? sum / static_cast<double>(drawn) : 0;
    const double exposure = mean > 0 ? 0.18 / mean : 1.0;
    std::vector<uint8_t> codes(static_cast<size_t>(width) * height * 3);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) {  // GL row 0 is the image's bottom
                const double v = std::clamp(exposure * px[((height - 1 - y) * width + x) * 4 + c], 0.0, 1.0);
                const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
                codes[(y * width + x) * 3 + c] = static_cast<uint8_t>(std::lround(255 * e));
            }
        }
    }
    std::ofstream out(o.output, std::ios::binary);
    out << "P6\n" << width << " " << height << "\n255\n";
    out.write(reinterpret_cast<const char*>(codes.data()), static_cast<std::streamsize>(codes.size()));
    if (!out) throw Fail(o.output + ": cannot write");
    std::printf("binder: %s drawn %dx%d (%ld pixels covered), exposure %.6g\n", g_manifest.c_str(), width, height,
                drawn, exposure);
    if (o.reference.empty()) return 0;

    const std::string ref = read_bytes(o.reference);
    const std::string header = "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
    if (ref.compare(0, header.size(), header) != 0 || ref.size() != header.size() + codes.size()) {
        throw Fail(o.reference + ": not a " + std::to_string(width) + "x" + std::to_string(height) + " binary PPM");
    }
    int worst = 0;
    long off = 0;
    for (size_t i = 0; i < codes.size(); ++i) {
        const int d = std::abs(static_cast<int>(codes[i]) - static_cast<uint8_t>(ref[header.size() + i]));
        worst = std::max(worst, d);
        off += d > 1 ? 1 : 0;
    }
    std::printf("binder: against %s: worst %d codes, %ld values more than 1 code off\n", o.reference.c_str(),
                worst, off);
    return worst <= 1 ? 0 : 1;  // one 8-bit code: the rounding of two float paths
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "binder: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--lighting") o.lighting = next();
        else if (a == "-o") o.output = next();
        else if (a == "--reference") o.reference = next();
        else if (a == "--load-choice") o.load_choice = std::stoi(next());
        else if (a == "--quad") o.quad_px = std::stoi(next());
        else if (o.manifest.empty() && a[0] != '-') o.manifest = a;
        else {
            std::fprintf(stderr, "binder: unknown argument %s\n", a.c_str());
            return 2;
        }
    }
    if (o.manifest.empty() || o.output.empty()) {
        std::fprintf(stderr, "usage: inlight_gles_binder MANIFEST|index.json [--lighting FILE] -o OUT.ppm "
                             "[--reference REF.ppm] [--load-choice I] [--quad N]\n");
        return 2;
    }
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "binder: %s\n", e.what());
        return 1;
    }
}
