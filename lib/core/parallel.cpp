#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <mutex>

namespace inlight::parallel {
namespace {
std::mutex g_mutex;
std::unique_ptr<tbb::global_control>& control() {
    static std::unique_ptr<tbb::global_control> c;
    return c;
}
}  // namespace

int set_thread_count(int threads) {
    std::lock_guard<std::mutex> lock(g_mutex);
    control().reset();
    if (threads > 0) {
        control() = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    }
    return thread_count();
}

int thread_count() {
    return static_cast<int>(
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

void for_chunks(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& fn) {
    if (n <= 0) return;
    if (grain < 1) grain = 1;
    const int64_t chunks = (n + grain - 1) / grain;
    tbb::parallel_for(
        tbb::blocked_range<int64_t>(0, chunks, 1),
        [&](const tbb::blocked_range<int64_t>& r) {
            for (int64_t c = r.begin(); c != r.end(); ++c) {
                const int64_t begin = c * grain;
                const int64_t end = begin + grain < n ? begin + grain : n;
                fn(begin, end);
            }
        },
        tbb::simple_partitioner());
}

}  // namespace inlight::parallel
