// Writes an analytic BTF (btf/synthetic.h) as a UBO2003 folder for the CLI tests:
//   inlight_make_test_btf OUT_DIR WIDTH HEIGHT RANK SCALE [LIGHTS_FILE VIEWS_FILE]
// Direction files default to the UBO2003 dome; 8-bit sRGB PNG, one folder per view.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "btf/synthetic.h"
#include "core/error.h"

int main(int argc, char** argv) {
    using namespace inlight::btf;
    if (argc != 6 && argc != 8) {
        std::fprintf(stderr, "usage: %s OUT_DIR WIDTH HEIGHT RANK SCALE [LIGHTS VIEWS]\n", argv[0]);
        return 2;
    }
    try {
        AnalyticBtfOptions o;
        o.width = std::atoi(argv[2]);
        o.height = std::atoi(argv[3]);
        o.rank = std::atoi(argv[4]);
        o.scale = std::atof(argv[5]);
        if (argc == 8) {
            o.lights = read_directions(argv[6]);
            o.views = read_directions(argv[7]);
        }
        write_ubo2003(AnalyticBtf(o), argv[1]);
    } catch (const inlight::Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
