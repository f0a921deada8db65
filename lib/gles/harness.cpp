#include "gles/harness.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <chrono>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "core/error.h"
#include "sh/sh.h"

namespace inlight::gles {
namespace {

bool has_token(const char* list, const std::string& token) {
    if (!list) return false;
    const std::string s = std::string(" ") + list + " ";
    return s.find(" " + token + " ") != std::string::npos;
}

std::string egl_error(const std::string& call) {
    return str("EGL: ", call, " failed (error 0x", std::hex, eglGetError(), ")");
}

std::string gl_string(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

}  // namespace

std::string ContextInfo::summary() const {
    return str(vendor, " | ", renderer, " | ", version, " (EGL platform ", platform, ")");
}

struct Context::Impl {
#if defined(__SANITIZE_ADDRESS__)
    // LeakSanitizer (make asan) is off on this thread while a context lives, first member so it
    // outlives the EGL teardown: Mesa's driver keeps what it allocates here (its one-time set-up,
    // its JIT's tables) for the process' life and is unloaded by eglTerminate, so its blocks
    // show as leaks with stacks that cannot be read, let alone told apart from ours.
    __lsan::ScopedDisabler driver_allocations_are_not_leaks;
#endif
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE;
    ContextInfo info;
};

Context::Context(int es_major) : m_impl(std::make_unique<Impl>()) {
    if (es_major != 2 && es_major != 3) throw UsageError(str("OpenGL ES ", es_major, ": 2 or 3"));
    Impl& m = *m_impl;
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display && has_token(client, "EGL_MESA_platform_surfaceless")) {
        m.display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                         nullptr);
        m.info.platform = "surfaceless_mesa";
    }
    if (m.display == EGL_NO_DISPLAY && get_platform_display &&
        has_token(client, "EGL_EXT_platform_device")) {
        auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
            eglGetProcAddress("eglQueryDevicesEXT"));
        EGLDeviceEXT device;
        EGLint count = 0;
        if (query_devices && query_devices(1, &device, &count) && count > 0) {
            m.display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
            m.info.platform = "device";
        }
    }
    if (m.display == EGL_NO_DISPLAY) {
        m.display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        m.info.platform = "default";
    }
    if (m.display == EGL_NO_DISPLAY) throw Error(egl_error("no display (eglGetDisplay)"));
    if (!eglInitialize(m.display, nullptr, nullptr)) throw Error(egl_error("eglInitialize"));
    if (!eglBindAPI(EGL_OPENGL_ES_API)) throw Error(egl_error("eglBindAPI(EGL_OPENGL_ES_API)"));
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE,
                                     es_major == 3 ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT,
                                     EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config;
    EGLint configs = 0;
    if (!eglChooseConfig(m.display, config_attribs, &config, 1, &configs) || configs < 1) {
        throw Error(egl_error(str("eglChooseConfig (OpenGL ES ", es_major, ", pbuffer)")));
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, es_major, EGL_NONE};
    m.context = eglCreateContext(m.display, config, EGL_NO_CONTEXT, context_attribs);
    if (m.context == EGL_NO_CONTEXT) {
        throw Error(egl_error(str("eglCreateContext (OpenGL ES ", es_major, ")")));
    }
    const char* display_ext = eglQueryString(m.display, EGL_EXTENSIONS);
    if (!has_token(display_ext, "EGL_KHR_surfaceless_context")) {
        const EGLint pbuffer[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        m.surface = eglCreatePbufferSurface(m.display, config, pbuffer);
        if (m.surface == EGL_NO_SURFACE) throw Error(egl_error("eglCreatePbufferSurface"));
    }
    if (!eglMakeCurrent(m.display, m.surface, m.surface, m.context)) {
        throw Error(egl_error("eglMakeCurrent"));
    }
    ContextInfo& i = m.info;
    i.vendor = gl_string(GL_VENDOR);
    i.renderer = gl_string(GL_RENDERER);
    i.version = gl_string(GL_VERSION);
    i.shading_language_version = gl_string(GL_SHADING_LANGUAGE_VERSION);
    glGetIntegerv(GL_MAX_FRAGMENT_UNIFORM_VECTORS, &i.limits.max_fragment_uniform_vectors);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &i.limits.max_texture_size);
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &i.limits.max_texture_image_units);
    const std::string extensions = gl_string(GL_EXTENSIONS);
    i.float_color_buffer = has_token(extensions.c_str(), "GL_EXT_color_buffer_float") ||
                           i.version.find("OpenGL ES 3.2") != std::string::npos;
}

Context::~Context() {
    Impl& m = *m_impl;
    eglMakeCurrent(m.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m.surface != EGL_NO_SURFACE) eglDestroySurface(m.display, m.surface);
    if (m.context != EGL_NO_CONTEXT) eglDestroyContext(m.display, m.context);
    eglTerminate(m.display);
}

const ContextInfo& Context::info() const { return m_impl->info; }

namespace {

/// GL objects of one draw, deleted on every exit path.
struct GlObjects {
    std::vector<GLuint> programs, shaders, textures, buffers, framebuffers, renderbuffers;
    ~GlObjects() {
        for (GLuint p : programs) glDeleteProgram(p);
        if (!renderbuffers.empty()) {
            glDeleteRenderbuffers(static_cast<GLsizei>(renderbuffers.size()), renderbuffers.data());
        }
        for (GLuint s : shaders) glDeleteShader(s);
        if (!textures.empty()) glDeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
        if (!buffers.empty()) glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
        if (!framebuffers.empty()) {
            glDeleteFramebuffers(static_cast<GLsizei>(framebuffers.size()), framebuffers.data());
        }
    }
};

GLuint compile(GlObjects& objs, GLenum stage, const std::string& source, const std::string& what) {
    const GLuint s = glCreateShader(stage);
    objs.shaders.push_back(s);
    const char* text = source.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetShaderInfoLog(s, sizeof(log), nullptr, log);
        throw Error(str("GLES variant ", what, ": the ",
                        stage == GL_VERTEX_SHADER ? "vertex" : "fragment",
                        " shader does not compile on ", gl_string(GL_RENDERER), ":\n", log));
    }
    return s;
}

GLuint texture(GlObjects& objs, int unit, GLint internal, GLenum format, GLenum type, int w, int h,
               const void* data) {
    GLuint t;
    glGenTextures(1, &t);
    objs.textures.push_back(t);
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, w, h, 0, format, type, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

void check_gl(const std::string& what) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) throw Error(str("GLES: ", what, ": GL error 0x", std::hex, e));
}

}  // namespace

namespace {

/// One item's program, textures and vertices, ready to draw.
struct Prepared {
    GLuint program = 0, buffer = 0;
    std::vector<std::pair<int, GLuint>> textures;  ///< unit, texture
    std::vector<std::pair<GLint, int>> attribs;    ///< location, (size << 8) | offset
    GLsizei vertices = 0;
};

Prepared prepare(GlObjects& objs, const Context& context, const DrawItem& item) {
    const Export& e = *item.variant;
    const Bindings& b = *item.bindings;
    const Mesh& mesh = *item.mesh;
    const bool es3 = e.manifest["variant"]["glsl_version"] == "300 es";
    Prepared p;
    p.program = glCreateProgram();
    objs.programs.push_back(p.program);
    glAttachShader(p.program, compile(objs, GL_VERTEX_SHADER, e.vertex_source, e.name));
    glAttachShader(p.program, compile(objs, GL_FRAGMENT_SHADER, e.fragment_source, e.name));
    glLinkProgram(p.program);
    GLint ok = 0;
    glGetProgramiv(p.program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetProgramInfoLog(p.program, sizeof(log), nullptr, log);
        throw Error(str("GLES variant ", e.name, ": the program does not link on ",
                        context.info().renderer, ":\n", log));
    }
    glUseProgram(p.program);
    auto loc = [&](const char* name) { return glGetUniformLocation(p.program, name); };

    // Uniforms.
    glUniformMatrix4fv(loc("u_clip_from_object"), 1, GL_FALSE, b.clip_from_object.data());
    glUniform2f(loc("u_uv_scale"), b.uv_scale.x(), b.uv_scale.y());
    const int k_count = sh::count(e.manifest["variant"]["sh_bands"].get<int>());
    if (b.sh.rows() < k_count || b.sh.cols() != 3) {
        throw Error(str("GLES variant ", e.name, ": needs ", k_count, "x3 lighting coefficients"));
    }
    if (e.lighting_layout == LightingLayout::kUniformArray) {
        std::vector<float> sh(static_cast<size_t>(k_count) * 3);
        for (int k = 0; k < k_count; ++k) {
            for (int c = 0; c < 3; ++c) sh[k * 3 + c] = static_cast<float>(b.sh(k, c));
        }
        glUniform3fv(loc("u_sh"), k_count, sh.data());
    }
    glUniform3f(loc("u_albedo"), b.albedo.x(), b.albedo.y(), b.albedo.z());
    const int lights = e.manifest.contains("lights") ? e.manifest["lights"]["count"].get<int>() : 0;
    if (static_cast<int>(b.lights.size()) != lights) {
        throw Error(str("GLES variant ", e.name, ": shades ", lights, " lights, ",
                        b.lights.size(), " given"));
    }
    if (lights > 0) {
        const LightUniformArrays a = light_uniform_arrays(b.lights);
        glUniform4fv(loc("u_light_direction"), lights, a.direction_sin.data());
        glUniform3fv(loc("u_light_irradiance"), lights, a.normal_irradiance.data());
    }

    // Textures in the manifest's units.
    for (const auto& t : e.manifest["textures"]) {
        const std::string name = t["uniform"];
        const int unit = t["unit"];
        GLuint tex = 0;
        const Texture8* given = nullptr;
        for (const auto& [n, img] : b.textures8) {
            if (n == name) given = img;
        }
        if (given) {
            tex = texture(objs, unit, es3 ? GL_RGBA8 : GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE, given->width,
                          given->height, given->rgba.data());
        } else if (name == "u_sh_texture") {
            const BoundLighting l = bind_lighting(e, b.sh);
            tex = l.bytes.empty()
                      ? texture(objs, unit, GL_RGBA32F, GL_RGBA, GL_FLOAT, l.width, l.height, l.texels.data())
                      : texture(objs, unit, GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE, l.width, l.height, l.bytes.data());
        } else if (name == "u_albedo_texture" || name == "u_normal_texture") {
            const bool albedo = name == "u_albedo_texture";
            const Texture8* img = albedo ? b.albedo_texture : b.normal_texture;
            // Level 0's size: the texture's, or (trilinear) the atlas' first level.
            const nlohmann::json& level0 = t.contains("mip") ? t["mip"]["levels"][0] : t;
            const Eigen::Vector2i want_px(level0["width"].get<int>(), level0["height"].get<int>());
            if (!img || img->width != want_px.x() || img->height != want_px.y()) {
                throw Error(str("GLES variant ", e.name, ": ", name, " needs a ", want_px.x(), "x",
                                want_px.y(), " RGBA8 image"));
            }
            if (t.contains("mip")) {  // trilinear: the atlas built from the image (the file's bytes)
                const MipAtlas8 atlas = mip_atlas_rgba8(img->rgba, want_px, albedo);
                if (atlas.width != t["width"] || atlas.height != t["height"]) {
                    throw Error(str("GLES variant ", e.name, ": ", name, "'s atlas is ", atlas.width, "x",
                                    atlas.height, ", the manifest says ", t["width"], "x", t["height"]));
                }
                tex = texture(objs, unit, es3 ? GL_RGBA8 : GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE,
                              atlas.width, atlas.height, atlas.rgba.data());
            } else {
                tex = texture(objs, unit, es3 ? GL_RGBA8 : GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE,
                              img->width, img->height, img->rgba.data());
            }
        } else if (e.table_layout == TableLayout::kRgba8Texture) {
            tex = texture(objs, unit, GL_RGBA, GL_RGBA, GL_UNSIGNED_BYTE, e.data_width,
                          e.data_height, e.table_bytes.data());
        } else {
            tex = texture(objs, unit, GL_RGBA32F, GL_RGBA, GL_FLOAT, e.data_width, e.data_height,
                          e.table_texels.data());
        }
        glUniform1i(loc(name.c_str()), unit);
        p.textures.emplace_back(unit, tex);
    }
    if (e.table_layout == TableLayout::kUniformArray) {
        glUniform4fv(loc("u_brdf"), e.data_width, e.table_texels.data());
    } else if (e.table_layout == TableLayout::kRgba8Texture && !e.table_scale_in_texture) {
        const auto n = static_cast<GLsizei>(e.table_scale.size() / 4);
        glUniform4fv(loc("u_brdf_scale"), n, e.table_scale.data());
        glUniform4fv(loc("u_brdf_offset"), n, e.table_offset.data());
    }
    for (const auto& [name, values] : b.float_arrays) {
        glUniform1fv(loc(name.c_str()), static_cast<GLsizei>(values.size()), values.data());
    }
    for (const auto& [name, values] : b.vec4_arrays) {
        glUniform4fv(loc(name.c_str()), static_cast<GLsizei>(values.size() / 4), values.data());
    }
    check_gl(str(e.name, ": binding uniforms and textures"));

    // Vertices: position, normal, tangent, uv interleaved.
    const size_t nv = mesh.position.size();
    std::vector<float> vbo;
    vbo.reserve(nv * 11);
    for (size_t i = 0; i < nv; ++i) {
        for (int c = 0; c < 3; ++c) vbo.push_back(mesh.position[i][c]);
        for (int c = 0; c < 3; ++c) vbo.push_back(mesh.normal[i][c]);
        for (int c = 0; c < 3; ++c) vbo.push_back(mesh.tangent.empty() ? 0.f : mesh.tangent[i][c]);
        for (int c = 0; c < 2; ++c) vbo.push_back(mesh.uv.empty() ? 0.f : mesh.uv[i][c]);
    }
    glGenBuffers(1, &p.buffer);
    objs.buffers.push_back(p.buffer);
    glBindBuffer(GL_ARRAY_BUFFER, p.buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vbo.size() * sizeof(float)), vbo.data(),
                 GL_STATIC_DRAW);
    const struct { const char* name; int size, offset; } attribs[] = {
        {"a_position", 3, 0}, {"a_normal", 3, 3}, {"a_tangent", 3, 6}, {"a_uv", 2, 9}};
    for (const auto& a : attribs) {
        const GLint l = glGetAttribLocation(p.program, a.name);
        if (l >= 0) p.attribs.emplace_back(l, (a.size << 8) | a.offset);
    }
    p.vertices = static_cast<GLsizei>(nv);
    return p;
}

void draw_prepared(const Prepared& p) {
    glUseProgram(p.program);
    for (const auto& [unit, tex] : p.textures) {
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(GL_TEXTURE_2D, tex);
    }
    glBindBuffer(GL_ARRAY_BUFFER, p.buffer);
    for (const auto& [l, packed] : p.attribs) {
        glEnableVertexAttribArray(static_cast<GLuint>(l));
        glVertexAttribPointer(static_cast<GLuint>(l), packed >> 8, GL_FLOAT, GL_FALSE,
                              11 * sizeof(float),
                              reinterpret_cast<const void*>((packed & 0xff) * sizeof(float)));
    }
    glDrawArrays(GL_TRIANGLES, 0, p.vertices);
    for (const auto& [l, packed] : p.attribs) glDisableVertexAttribArray(static_cast<GLuint>(l));
}

}  // namespace

Readback draw(const Context& context, const Export& e, const Bindings& b, const Mesh& mesh,
              int width, int height, TargetFormat format, int repeat) {
    return draw(context, {DrawItem{&e, &b, &mesh}}, width, height, format, repeat);
}

Readback draw(const Context& context, const std::vector<DrawItem>& items, int width, int height,
              TargetFormat format, int repeat) {
    const std::string what = items.empty() ? std::string("(nothing)") : items[0].variant->name;
    if (format == TargetFormat::kRgba32f && !context.info().float_color_buffer) {
        throw Error(str("GLES variant ", what, ": ", context.info().renderer,
                        " cannot render to RGBA32F (no EXT_color_buffer_float)"));
    }
    GlObjects objs;
    std::vector<Prepared> prepared;
    int units = 0;
    for (const DrawItem& item : items) {
        prepared.push_back(prepare(objs, context, item));
        units = std::max(units, static_cast<int>(item.variant->manifest["textures"].size()));
    }

    // Target: colour texture (the unit after every item's) and a depth renderbuffer.
    GLuint fbo;
    glGenFramebuffers(1, &fbo);
    objs.framebuffers.push_back(fbo);
    const bool f32 = format == TargetFormat::kRgba32f;
    const bool es3 = context.info().version.find("OpenGL ES 3") != std::string::npos;
    const GLuint target = texture(objs, units, f32 ? GL_RGBA32F : (es3 ? GL_RGBA8 : GL_RGBA),
                                  GL_RGBA, f32 ? GL_FLOAT : GL_UNSIGNED_BYTE, width, height,
                                  nullptr);
    GLuint depth;
    glGenRenderbuffers(1, &depth);
    objs.renderbuffers.push_back(depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT16, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw Error(str("GLES variant ", what, ": the ", f32 ? "RGBA32F" : "RGBA8",
                        " framebuffer is incomplete on ", context.info().renderer));
    }
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);  // RGBA8: round, do not dither
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearColor(0, 0, 0, 0);
    glClearDepthf(1.0f);
    Readback out;
    for (int r = 0; r < std::max(repeat, 1); ++r) {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glFinish();
        const auto t0 = std::chrono::steady_clock::now();
        for (const Prepared& p : prepared) draw_prepared(p);
        glFinish();
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        out.draw_ms = r == 0 ? ms : std::min(out.draw_ms, ms);  // the least disturbed run
    }
    check_gl(str(what, ": drawing"));

    out.width = width;
    out.height = height;
    out.rgba.resize(static_cast<size_t>(width) * height * 4);
    std::vector<float> rows(out.rgba.size());
    if (f32) {
        glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rows.data());
    } else {
        std::vector<uint8_t> bytes(out.rgba.size());
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
        for (size_t i = 0; i < bytes.size(); ++i) rows[i] = bytes[i] / 255.0f;
    }
    check_gl(str(what, ": reading back"));
    const size_t row = static_cast<size_t>(width) * 4;
    for (int y = 0; y < height; ++y) {  // GL row 0 is the bottom
        std::memcpy(&out.rgba[y * row], &rows[(height - 1 - y) * row], row * sizeof(float));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_DEPTH_TEST);
    return out;
}

}  // namespace inlight::gles
