// testing/testing.h: locating real data for tests; a test that needs absent data skips.
#pragma once

#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"

namespace inlight::testing {

/// The project's ../shared directory (from INLIGHT_SHARED_DIR, set by ctest), or "" if absent.
std::string shared_dir();
/// ../shared/data/<sub>, or "" if it does not exist. With ../shared present, a missing <sub> is
/// also a test failure (a broken path must not silently turn the real-data checks into skips);
/// without ../shared (a clone without it) the caller skips.
std::string shared_data(const std::string& sub);
/// The blender-data studio-light HDRIs (/usr/share/blender/datafiles/studiolights/world), or "".
std::string blender_hdri_dir();
/// The eight blender-data HDRI names.
inline const char* const kBlenderHdris[] = {"city",  "courtyard", "forest", "interior",
                                             "night", "studio",    "sunrise", "sunset"};
/// A fresh empty temporary directory for one test (removed by the OS, not by the test).
std::string temp_dir(const std::string& name);

/// Runs fn, expects it to throw inlight::Error, and returns the message ("" and a test failure
/// when nothing is thrown).
template <typename Fn>
std::string error_of(Fn fn) {
    try {
        fn();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected inlight::Error";
    return "";
}

/// A w x h image of c channels with values uniform in [lo, hi), from a fixed seed.
template <typename ImageT, typename ColorSpaceT>
ImageT random_image(int w, int h, int c, float lo, float hi, unsigned seed, ColorSpaceT cs) {
    ImageT img(w, h, c, cs);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    for (float& v : img.pixels) v = u(rng);
    return img;
}

}  // namespace inlight::testing

/// Skips the current test with a message when `path` (a string) is empty, unless a failure is
/// already recorded (shared_data's data set missing from a present ../shared): then it returns.
#define INLIGHT_SKIP_IF_MISSING(path, what)                                   \
    if ((path).empty()) {                                                     \
        if (::testing::Test::HasFailure()) return;                            \
        GTEST_SKIP() << what << " not found; skipping (see shared/data/README.md)"; \
    }
