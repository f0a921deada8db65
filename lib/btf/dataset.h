// btf/dataset.h: a BTF as a source of images and of view groups, and the reader of BTF folders
// and zip files in UBO2003 naming (docs/conventions.md, "BTF sample frame and direction naming").
//
// In memory every BTF image is linear float RGB (colour space linear_srgb): 8- and 16-bit files
// are sRGB-decoded (as Bonn ships and the capture writes them), float EXR is taken as linear.
// A view group is one matrix with a row per pixel (row = y * width + x, y = 0 the top row) and a
// column per (view, light, channel): column = (view_in_group * n_lights + light) * 3 + channel.
// This is the thesis' matrix A (section 4.3.1): columns are the channel images of the group.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "btf/dome.h"
#include "image/image.h"

namespace inlight::btf {

/// The directions and image size of a BTF.
struct BtfShape {
    std::vector<Direction> lights;  ///< light directions, sample frame
    std::vector<Direction> views;   ///< view directions, sample frame
    int width = 0;                  ///< pixels
    int height = 0;                 ///< pixels

    int n_lights() const { return static_cast<int>(lights.size()); }
    int n_views() const { return static_cast<int>(views.size()); }
    int64_t pixel_count() const { return static_cast<int64_t>(width) * height; }
    /// Columns of the matrix of a group of `views` views: 3 * n_lights * views.
    int64_t group_columns(int views) const { return int64_t(3) * n_lights() * views; }
    /// Float samples of the whole BTF: pixels * 3 * n_lights * n_views.
    double sample_count() const { return double(pixel_count()) * group_columns(n_views()); }
};

/// One term of a weighted sum of a BTF's images: image (light, view) times a weight per channel.
struct ImageTerm {
    int light = 0;
    int view = 0;
    Eigen::Vector3d weight = Eigen::Vector3d::Zero();  ///< per linear_srgb channel
};

/// Anything that yields a BTF's images: a folder or zip file, or an analytic BTF in tests.
/// Implementations must be safe to call from several threads at once.
class BtfSource {
  public:
    virtual ~BtfSource() = default;
    virtual const BtfShape& shape() const = 0;
    /// The image of one light and one view: width x height x 3, linear_srgb.
    /// Precondition: 0 <= light < n_lights, 0 <= view < n_views (checked).
    virtual image::Image read_image(int light, int view) const = 0;
    /// The matrix of a view group (layout in the file comment), resized to fit. Images are read
    /// in parallel; the result does not depend on the thread count.
    /// Precondition: views are valid, distinct indices (checked).
    virtual void read_group(const std::vector<int>& views, Eigen::MatrixXf& out) const;
    /// sum_t weight_t x image(light_t, view_t) per channel: width x height x 3, linear_srgb,
    /// summed in double in the terms' order (the same bits for any thread count). Angular
    /// interpolation (btf/interp.h) and environment shading (btf/lighting.h) are such sums.
    /// This default reads every image; a compressed BTF sums its weights first.
    /// Precondition: every term's light and view are valid (checked).
    virtual image::Image combine(const std::vector<ImageTerm>& terms) const;
};

/// How a BTF folder or zip file is read.
struct OpenOptions {
    /// Direction files of the light and view sets; "" = the file a folder's capture.json names
    /// under "light_directions" / "view_directions" (render capture-btf writes them for a set
    /// other than the dome; not read from zip files), else the UBO2003 dome.
    std::string light_directions;
    std::string view_directions;
    bool decode_srgb = true;       ///< 8/16-bit files are sRGB-encoded (false: linear values)
    int max_side_px = 16384;       ///< larger images are rejected as corrupt or hostile
};

/// Where each image of a BTF folder or zip file is, and what the files are.
struct BtfIndex {
    BtfShape shape;
    std::string root;  ///< the folder or zip file
    bool is_zip = false;
    /// files[view * n_lights + light]: path relative to root, or the zip entry's name
    std::vector<std::string> files;
    std::string format;        ///< OpenImageIO format name of the files ("png", "jpeg", ...)
    int file_channels = 0;     ///< channels in the files (1: grey, replicated; 4: alpha dropped)
    int bits_per_channel = 0;  ///< 8, 16, or 16/32 for half/float EXR
    bool is_float = false;
    uint64_t stored_bytes = 0;         ///< sum of the image files' sizes (the BTF's storage)
    std::vector<std::string> ignored;  ///< files without the UBO2003 pattern (not BTF images)
};

/// A BTF stored as image files in UBO2003 naming: a folder (images at any depth, e.g. one
/// folder per view, with or without a prefix before `tl`) or a zip file read in place.
class FolderBtf : public BtfSource {
  public:
    /// Indexes `path` (folder, or a .zip file) and checks every image's header. Throws Error,
    /// naming the files, for: a name whose light or view is not in its direction set (the
    /// nearest direction is named), two files of the same light and view, missing images (the
    /// first few are named, with the count), a per-view folder whose angles disagree with the
    /// file's, and images whose size, channel count, bit depth or format differ from the first
    /// one's; also for no images at all and unreadable files.
    static std::unique_ptr<FolderBtf> open(const std::string& path,
                                           const OpenOptions& options = {});
    /// The same from a zip archive held in memory: the entry point for fuzzing the reader
    /// (bad bytes throw Error, never crash).
    static std::unique_ptr<FolderBtf> open_zip_memory(const void* data, size_t size,
                                                      const std::string& name,
                                                      const OpenOptions& options = {});
    ~FolderBtf() override;

    const BtfShape& shape() const override { return m_index.shape; }
    const BtfIndex& index() const { return m_index; }
    /// Reads and decodes one file. Throws Error naming it when it cannot be decoded or no longer
    /// matches the header checked at open().
    image::Image read_image(int light, int view) const override;

  private:
    FolderBtf() = default;
    void build(const OpenOptions& options);
    std::string read_bytes(int file, uint64_t max_bytes) const;

    BtfIndex m_index;
    OpenOptions m_options;
    struct Zip;
    std::unique_ptr<Zip> m_zip;
};

/// Fuzzing entry point: opens `data` as a zip archive of a BTF with the given direction sets
/// (the options' files) and decodes every image it indexes. Throws Error on bad input.
void fuzz_read_btf_zip(const uint8_t* data, size_t size, const OpenOptions& options = {});

/// How views are put into groups of k.
enum class ViewGrouping {
    /// Neighbouring directions: groups are seeded from the rim inward (largest theta first, then
    /// set order), each grown by complete linkage (the next view is the ungrouped one whose
    /// farthest group member is nearest; ties to the lower index); the last groups hold what
    /// is left and may have fewer than k views.
    kNeighbours,
    /// k consecutive views of the set's order, {0..k-1}, {k..2k-1}, ...; the last group holds
    /// the rest. The BTF thesis' grouping (section 4.3: "k neighbour camera directions" of the
    /// Bonn order, rings by theta and each ring by phi), kept as its baseline.
    kConsecutive,
};
std::string to_string(ViewGrouping g);  ///< "neighbours", "consecutive"

/// The views of each group of k views, grouped as `grouping` says. Each group's views are
/// sorted. k = 1 gives one group per view (PCA RF), k >= n_views one group (PCA BTF).
/// Precondition: k >= 1 (checked).
std::vector<std::vector<int>> view_groups(const std::vector<Direction>& views, int k,
                                          ViewGrouping grouping = ViewGrouping::kNeighbours);

}  // namespace inlight::btf
