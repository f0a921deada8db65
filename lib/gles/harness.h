// gles/harness.h: runs an exported variant (gles/export.h) headless through EGL on whatever
// conforming driver the machine has, into an offscreen framebuffer (RGBA32F or RGBA8), and
// reads the pixels back.
//
// Display: EGL_PLATFORM_SURFACELESS_MESA when the client offers it (Mesa: llvmpipe or a GPU
// without a window system), else the first device of EGL_EXT_platform_device (NVIDIA's
// headless driver), else the default display. Context: OpenGL ES `es_major` (2 or 3) without
// a surface (EGL_KHR_surfaceless_context) or with a 1x1 pbuffer. Which vendor, renderer and
// version ran is in ContextInfo (print it: a result belongs to its driver).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gles/export.h"

namespace inlight::gles {

struct ContextInfo {
    std::string platform;  ///< "surfaceless_mesa" | "device" | "default"
    std::string vendor, renderer, version, shading_language_version;  ///< glGetString
    Limits limits;                     ///< what the driver offers
    bool float_color_buffer = false;   ///< RGBA32F renderable (ES 3.2 or EXT_color_buffer_float)
    std::string summary() const;       ///< "vendor | renderer | version (platform)"
};

/// An EGL display and OpenGL ES context, current on the creating thread while it lives. Not
/// copyable; one per thread.
class Context {
public:
    /// Throws Error naming the EGL call that failed and its error code.
    explicit Context(int es_major);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    const ContextInfo& info() const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// An 8-bit RGBA image, rows top first (the app's PNG as loaded).
struct Texture8 {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  ///< width * height * 4
};

/// Triangles, one entry per vertex: position (device frame), normal, tangent (dp/du), uv.
struct Mesh {
    std::vector<Eigen::Vector3f> position, normal, tangent;
    std::vector<Eigen::Vector2f> uv;
};

/// Everything the manifest asks the app to bind.
struct Bindings {
    Eigen::Matrix4f clip_from_object = Eigen::Matrix4f::Identity();
    Eigen::Vector2f uv_scale{1, 1};
    Eigen::MatrixXd sh;  ///< count(bands) (or more) x 3 lighting coefficients, device frame
    Eigen::Vector3f albedo{1, 1, 1};
    /// Dominant lights, device frame (exactly the variant's count; set as light_uniforms()).
    std::vector<envmap::DirectionalLight> lights;
    const Texture8* albedo_texture = nullptr;  ///< sRGB bytes; required iff the variant has one
    const Texture8* normal_texture = nullptr;  ///< data bytes; required iff the variant has one
    /// Further `uniform float name[n]` arrays (for shaders that are not exports, e.g. the
    /// brdf/glsl.h lookup snippet); set with glUniform1fv.
    std::vector<std::pair<std::string, std::vector<float>>> float_arrays;
    /// Further `uniform vec4 name[n]` arrays (4 floats each; glUniform4fv), e.g. the BTF
    /// export's weights (gles/btf_export.h).
    std::vector<std::pair<std::string, std::vector<float>>> vec4_arrays;
    /// RGBA8 textures of the manifest's "textures" entries by uniform name (taking precedence
    /// over the export's own data), e.g. the BTF export's group atlases.
    std::vector<std::pair<std::string, const Texture8*>> textures8;
};

enum class TargetFormat { kRgba32f, kRgba8 };

/// Pixels read back: rgba floats (8-bit targets as code / 255), row 0 = top of the image.
struct Readback {
    int width = 0, height = 0;
    std::vector<float> rgba;
    double draw_ms = 0;  ///< glDrawArrays to glFinish, wall clock
    float at(int x, int y, int c) const { return rgba[(static_cast<size_t>(y) * width + x) * 4 + c]; }
};

/// Compiles and links the variant (compile or link failure: Error naming the variant, the
/// stage and the driver's log), binds `bindings` and the export's table data, draws `mesh`
/// into a width x height framebuffer of `format` cleared to 0 and reads it back. Window y is
/// flipped so that clip y = +1 is row 0. Throws Error when the context cannot render to
/// `format` (RGBA32F without float colour buffers).
Readback draw(const Context& context, const Export& variant, const Bindings& bindings,
              const Mesh& mesh, int width, int height, TargetFormat format, int repeat = 1);

/// One variant with its bindings and mesh (pointers: the caller owns them).
struct DrawItem {
    const Export* variant = nullptr;
    const Bindings* bindings = nullptr;
    const Mesh* mesh = nullptr;
};
/// Several items into one framebuffer with a 16-bit depth test (a scene: one item per
/// material); alpha 0 where nothing was drawn. `repeat` draws time the frame, the least
/// disturbed is kept in draw_ms.
Readback draw(const Context& context, const std::vector<DrawItem>& items, int width, int height,
              TargetFormat format, int repeat = 1);

}  // namespace inlight::gles
