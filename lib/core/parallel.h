// core/parallel.h: TBB loops whose results do not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace inlight::parallel {

/// Limits TBB to `threads` workers for the rest of the process (0 = all hardware threads).
/// Returns the number in effect.
int set_thread_count(int threads);
/// The number of worker threads currently allowed.
int thread_count();

/// Calls fn(begin, end) for the chunks [k*grain, min(n, (k+1)*grain)) of [0, n), in parallel.
/// Chunk boundaries depend only on n and grain, never on the thread count.
void for_chunks(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& fn);

/// Deterministic reduction: each fixed chunk produces a partial result with
/// chunk_fn(begin, end) -> T, then the partials are combined left to right in chunk order, so
/// the floating-point result is bit-identical for any thread count.
template <typename T, typename ChunkFn, typename Combine>
T reduce(int64_t n, int64_t grain, T identity, ChunkFn chunk_fn, Combine combine) {
    if (n <= 0) return identity;
    const int64_t chunks = (n + grain - 1) / grain;
    std::vector<T> partial(static_cast<size_t>(chunks), identity);
    for_chunks(n, grain, [&](int64_t begin, int64_t end) {
        partial[static_cast<size_t>(begin / grain)] = chunk_fn(begin, end);
    });
    T total = identity;
    for (auto& p : partial) total = combine(std::move(total), p);
    return total;
}

}  // namespace inlight::parallel
