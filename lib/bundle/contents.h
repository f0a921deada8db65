// bundle/contents.h: checks that the manifests a fabric bundle carries inside it agree with the
// bundle's own manifest (docs/bundle-format.md, "What the reader rejects"): every file an
// exported GLES variant's manifest names, and every image and the stream order of the
// compressed BTF's manifest (btf-pca.json), is in the bundle with the right role, and the
// bundle's stream_index order is the BTF's stream order.
#pragma once

#include <string>

#include "bundle/manifest.h"

namespace inlight::bundle {

/// Checks the inner manifests of the bundle folder `dir` whose (already validated) manifest is
/// `manifest`; the files' sizes and hashes must have been checked before (read_bundle does).
/// Paths inside an inner manifest are relative to that manifest's folder. Throws Error naming
/// the inner manifest and the entry when:
///   - a shader_manifest (format "inlight_gles_export") names a file (null = none, as a Lambert
///     material's brdf_data) the bundle does not list,
///     or lists with another role (vertex -> shader_vertex, fragment -> shader_fragment,
///     brdf_data -> shader_data); the shader_index names a variant manifest that is not a
///     shader_manifest of the bundle;
///   - btf files are present without a btf_manifest, or the btf_manifest (format
///     "inlight-btf-pca") names a mean or component image the bundle does not hold with role
///     btf_mean / btf_component, or the bundle's btf_component files are not exactly the
///     manifest's stream, in its order (stream_index k = the k-th entry of "stream"), or a
///     BTF with components lacks its btf_weights;
///   - btf_gles_* files are present without a btf_gles_manifest, or the btf_gles_manifest
///     (format "inlight_btf_gles_export", docs/btf-gles.md "In the bundle") has no btf_manifest
///     beside it, names a shader or matrices file the bundle does not hold with role
///     btf_gles_vertex / btf_gles_fragment / btf_gles_matrices (or matrices of another size),
///     does not say textures.atlas_files false, names as an atlas channel's source a file that is
///     not a btf_mean / btf_component of the bundle, or loads a variant it does not have.
void check_contents(const Manifest& manifest, const std::string& dir);

}  // namespace inlight::bundle
