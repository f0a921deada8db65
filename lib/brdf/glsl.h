// brdf/glsl.h: the GLSL ES 3.0 text of the shader-side lookup of a baked table: constants, the
// uniform array or RGBA32F texture declaration, brdf_grid_coord() and brdf_sh_lookup(). It is
// the same computation as grid_coord() + lookup() in C++ (same float constants and order).
#pragma once

#include <string>

#include "brdf/table.h"

namespace inlight::brdf {

/// GLSL ES 3.0 source to paste after "#version 300 es". By default it declares
///   uniform float u_brdf_coeffs[channels * rows * cols * coeff_count];  (table.h layout)
/// and with "#define BRDF_USE_TEXTURE" before it instead
///   uniform highp sampler2D u_brdf_texture;  (texture_texels() layout, read with texelFetch)
/// Both give  void brdf_sh_lookup(vec3 n, int channel, out float coeffs[BRDF_NCOEFFS]).
/// GLES 3.0 guarantees only 224 fragment uniform vectors and a float array may take one vector
/// per element: tables over ~200 floats need the texture path.
std::string glsl_lookup_source(const Table& table);

/// A float literal that parses back to the same float (9 significant digits, always with a
/// point or exponent), as every emitted shader prints its constants.
std::string glsl_float(float f);

/// GLSL ES source of  void brdf_grid_coord(vec3 n, out ivec4 cell, out vec2 f)  for `grid`
/// (cell = (r0, r1, c0, c1), f = fractions toward r1 and c1): grid_coord() in GLSL. It uses the
/// constants BRDF_ROWS and BRDF_COLS, which the caller declares. glsl_version is 300 (GLSL ES
/// 3.00) or 100 (GLSL ES 1.00, which has no integer % or min: the same values through float
/// mod and a comparison).
std::string glsl_grid_coord_source(const Grid& grid, int glsl_version);

/// GLSL ES (1.00 and 3.00) source of  float atan2_f32(float y, float x): atan(y, x) to float
/// accuracy (Cephes atanf from +, *, /), which glsl_grid_coord_source() includes for the grids
/// that need it (glsl_grid_coord_has_atan2) and other shaders reuse.
std::string glsl_atan2_source();
bool glsl_grid_coord_has_atan2(const Grid& grid);

}  // namespace inlight::brdf
