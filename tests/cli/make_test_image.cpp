// Writes small synthetic images for the CLI tests:
//   inlight_make_test_image OUT.exr WIDTH HEIGHT VALUE [X Y SPECIAL]
// fills 3 channels with VALUE; SPECIAL ("nan", "inf" or a number) goes into pixel (X, Y).
// A .png is written linearly (8-bit code = round(255 * value)), as a camera frame's codes.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "image/image.h"

int main(int argc, char** argv) {
    if (argc != 5 && argc != 8) {
        std::fprintf(stderr, "usage: %s OUT WIDTH HEIGHT VALUE [X Y nan|inf|NUMBER]\n", argv[0]);
        return 2;
    }
    inlight::image::Image img(std::atoi(argv[2]), std::atoi(argv[3]), 3);
    for (float& p : img.pixels) p = std::strtof(argv[4], nullptr);
    if (argc == 8) {
        const std::string s = argv[7];
        const float v = s == "nan" ? NAN : s == "inf" ? INFINITY : std::strtof(argv[7], nullptr);
        for (int c = 0; c < 3; ++c) img.at(std::atoi(argv[5]), std::atoi(argv[6]), c) = v;
    }
    inlight::image::WriteOptions wo;
    wo.encode_srgb = false;
    inlight::image::write_image(argv[1], img, wo);
    return 0;
}
