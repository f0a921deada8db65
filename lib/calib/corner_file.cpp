#include "calib/corner_file.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"

namespace inlight::calib {

namespace {

void flatten(const cv::FileNode& node, std::vector<double>& out) {
    if (node.isSeq()) {
        for (auto it = node.begin(); it != node.end(); ++it) flatten(*it, out);
    } else if (node.isMap()) {
        cv::Mat m;
        node >> m;
        cv::Mat d;
        m.convertTo(d, CV_64F);
        d = d.reshape(1, 1);
        for (int i = 0; i < d.cols; ++i) out.push_back(d.at<double>(0, i));
    } else if (node.isReal() || node.isInt()) {
        out.push_back(static_cast<double>(node));
    }
}

// OpenCV 4.6's YAML parser never returns on a document whose top-level collection is indented
// and followed by a line indented less (e.g. "   - 1\nx"): its root collection ends on the dedent
// and the stream loop then steps over the text without progress. OpenCV itself writes every
// top-level key at column 0, so such a file is refused before OpenCV sees it. Applies to YAML
// (by extension, or content not starting like XML or JSON, as OpenCV decides).
void check_yaml_layout(const std::string& path) {
    const std::string ext = fs::extension(path);
    if (ext == "xml" || ext == "json" || ext == "gz") return;
    const std::string text = fs::read_file(path);
    const size_t first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return;
    if (ext != "yml" && ext != "yaml" && (text[first] == '<' || text[first] == '{')) return;
    bool document_start = true;  // the next content line opens a document's root collection
    size_t line_no = 0;
    for (size_t at = 0; at < text.size();) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(at, end - at);
        at = end + 1;
        ++line_no;
        const size_t c = line.find_first_not_of(" \t\r");
        if (c == std::string::npos || line[c] == '#' || (c == 0 && line[0] == '%')) continue;
        if (line.compare(0, 3, "---") == 0 || line.compare(0, 3, "...") == 0) {
            if (line.find_first_not_of(" \t\r", 3) != std::string::npos) {
                throw Error(str(path, ":", line_no, ": text after '", line.substr(0, 3),
                                "' on the same line is not supported"));
            }
            document_start = true;
            continue;
        }
        if (document_start && c != 0) {
            throw Error(str(path, ":", line_no,
                            ": the top-level collection must start at column 1 (it is indented)"));
        }
        // A line at column 1 starts a key of the top-level map: OpenCV writes keys that start
        // with a letter or '_'. "--a:" over an indented sequence and an empty key made OpenCV
        // 4.6's parser throw std::length_error through a frame that cannot pass it on:
        // std::terminate (fuzz/regressions/corners). A top-level sequence ("- 1") is refused here
        // too; OpenCV asserted on some of those.
        const unsigned char key_start = static_cast<unsigned char>(line[c]);
        if (c == 0 && !std::isalpha(key_start) && key_start != '_') {
            throw Error(str(path, ":", line_no, ": a top-level key must start with a letter or '_', not '",
                            line.substr(0, 1), "' (the file must be a map of named nodes, as OpenCV writes)"));
        }
        document_start = false;
    }
}

cv::FileStorage open_read(const std::string& path) {
    fs::check_input_file(path);
    check_yaml_layout(path);
    cv::FileStorage fs;
    try {
        fs.open(path, cv::FileStorage::READ);
    } catch (const cv::Exception& e) {
        throw Error(str(path, ": not an OpenCV FileStorage file (", e.err, ")"));
    }
    if (!fs.isOpened()) throw Error(str(path, ": cannot open as an OpenCV FileStorage file"));
    if (!fs.root().isMap()) throw Error(str(path, ": the top level is not a map of named nodes"));
    return fs;
}

std::vector<std::vector<double>> read_nodes(cv::FileStorage& fs, const std::string& path,
                                            int per_point) {
    std::vector<std::vector<double>> nodes;
    for (int i = 0;; ++i) {
        const cv::FileNode n = fs[str("image_", i)];
        if (n.empty() || n.isNone()) break;
        std::vector<double> values;
        flatten(n, values);
        if (values.empty() || values.size() % static_cast<size_t>(per_point) != 0) {
            throw Error(str(path, ": node image_", i, " holds ", values.size(),
                            " numbers, not a multiple of ", per_point));
        }
        for (size_t k = 0; k < values.size(); ++k) {
            if (!std::isfinite(values[k])) {
                throw Error(str(path, ": node image_", i, ", point ", k / per_point, ": ",
                                values[k], " is not a finite number"));
            }
        }
        nodes.push_back(std::move(values));
    }
    if (nodes.empty()) throw Error(str(path, ": no node image_0"));
    return nodes;
}

/// image_width / image_height: absent (0), or an integer in [1, 65536].
int read_size(cv::FileStorage& fs, const char* key, const std::string& path) {
    const cv::FileNode n = fs[key];
    if (n.empty() || n.isNone()) return 0;
    if (!n.isInt() || static_cast<int>(n) < 1 || static_cast<int>(n) > 65536) {
        throw Error(str(path, ": ", key, " must be an integer in [1, 65536]"));
    }
    return static_cast<int>(n);
}

}  // namespace

namespace {

CornerSet read_checked(const std::string& image_points_path, const std::string& object_points_path,
                       const BoardSpec& board);

}  // namespace

CornerSet read_corner_files(const std::string& image_points_path,
                            const std::string& object_points_path, const BoardSpec& board) {
    // OpenCV reports a file whose top level is not a map, or a node it cannot convert, with a
    // cv::Exception (an assertion inside FileNode); that is bad input, named here.
    try {
        return read_checked(image_points_path, object_points_path, board);
    } catch (const cv::Exception& e) {
        throw Error(str(image_points_path,
                        object_points_path.empty() ? "" : " / " + object_points_path,
                        ": not a corner file OpenCV can read (", e.err, ")"));
    }
}

namespace {

CornerSet read_checked(const std::string& image_points_path, const std::string& object_points_path,
                       const BoardSpec& board) {
    CornerSet set;
    cv::FileStorage fi = open_read(image_points_path);
    const auto images = read_nodes(fi, image_points_path, 2);
    set.width = read_size(fi, "image_width", image_points_path);
    set.height = read_size(fi, "image_height", image_points_path);
    std::vector<std::string> names;
    if (!fi["files"].empty()) {
        for (auto it = fi["files"].begin(); it != fi["files"].end(); ++it) {
            names.push_back(static_cast<std::string>(*it));
        }
    }
    std::vector<std::vector<double>> objects;
    if (!object_points_path.empty()) {
        cv::FileStorage fo = open_read(object_points_path);
        objects = read_nodes(fo, object_points_path, 3);
        if (objects.size() != images.size()) {
            throw Error(str(object_points_path, ": ", log::count(int64_t(objects.size()), "view"), ", but ",
                            image_points_path, " has ", images.size()));
        }
    }
    for (size_t i = 0; i < images.size(); ++i) {
        View v;
        v.name = i < names.size() ? names[i] : str("image_", i);
        for (size_t k = 0; k + 1 < images[i].size(); k += 2) {
            v.image_points.emplace_back(images[i][k], images[i][k + 1]);
        }
        if (!objects.empty()) {
            for (size_t k = 0; k + 2 < objects[i].size(); k += 3) {
                v.object_points.emplace_back(objects[i][k], objects[i][k + 1], objects[i][k + 2]);
            }
        } else {
            v.object_points = board_object_points(board);
        }
        if (v.object_points.size() != v.image_points.size()) {
            throw Error(str(image_points_path, ": image_", i, " has ", v.image_points.size(),
                            " points but its object points number ", v.object_points.size(),
                            objects.empty() ? " (from --board)" : ""));
        }
        set.views.push_back(std::move(v));
    }
    return set;
}

}  // namespace

void write_corner_files(const std::string& image_points_path, const std::string& object_points_path,
                        const std::vector<View>& views, int width, int height) {
    auto write = [&](const std::string& path, bool image) {
        fs::write_atomic(path, [&](const std::string& tmp) {
            cv::FileStorage out(tmp, cv::FileStorage::WRITE);
            if (!out.isOpened()) throw Error(str(path, ": cannot write"));
            if (image) {
                out << "image_width" << width << "image_height" << height;
                out << "files"
                    << "[";
                for (const View& v : views) out << v.name;
                out << "]";
            }
            for (size_t i = 0; i < views.size(); ++i) {
                out << str("image_", i) << "[:";
                if (image) {
                    for (const auto& p : views[i].image_points) out << p.x() << p.y();
                } else {
                    for (const auto& p : views[i].object_points) out << p.x() << p.y() << p.z();
                }
                out << "]";
            }
            out.release();
        });
    };
    write(image_points_path, true);
    write(object_points_path, false);
}

}  // namespace inlight::calib
