// Fork-join loops on oneTBB's persistent work-stealing pool, the one Embree builds its BVHs
// on. An incremental update is many short loops: starting threads for each one cost more than
// the work in most of them (bench/results/tbb_pool.md).
#pragma once
#include <algorithm>
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace radiosity {

// The cores this process may use (TBB's default concurrency: the affinity mask, cgroup quota).
int hardware_threads();

namespace detail {
// An arena of at most `threads` threads (parallel_for's for a limit below the cores), made at
// the first loop that asks for that limit and kept for the process: making one per loop costs
// more than a short loop (measured in bench/bench_parallel.cpp).
tbb::task_arena& limited_arena(int threads);

// parallel_for's loop proper, in the current arena and isolation: items handed out in ranges
// of `grain` or more. A range may be many grains long (TBB splits only as far as threads ask
// for work): after each grain it stops if an item threw elsewhere.
template <class F, class P>
void grain_loop(size_t n, size_t grain, F& f, P&& partitioner) {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, n, grain),
        [&](const tbb::blocked_range<size_t>& r) {
            for (size_t b = r.begin(); b < r.end(); b += grain) {
                if (b != r.begin() && tbb::is_current_task_group_canceling()) return;
                const size_t e = std::min(r.end(), b + grain);
                for (size_t i = b; i < e; ++i) f(i);
            }
        },
        partitioner);
}
}  // namespace detail

// Calls f(i) for i in [0, n) on up to `threads` threads (0 = all cores; a limit above the
// cores gives all cores). threads == 1, or n <= grain, runs on the caller alone. Items are
// handed out in ranges of `grain` or more, split further whenever a thread runs out of work,
// so uneven items balance themselves. The first exception from f stops the loop (each thread finishes at
// most the grain it is in) and is re-thrown on the caller once no item runs any more.
// Which thread runs an item, and in what order, varies from run to run: f(i) must not depend
// on it, so results are the same for any `threads` and any schedule.
template <class F>
void parallel_for(size_t n, int threads, F&& f, size_t grain = 64) {
    if (n == 0) return;
    if (threads <= 0 || threads > hardware_threads()) threads = hardware_threads();
    if (grain == 0) grain = 1;
    if (threads == 1 || n <= grain) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    auto loop = [&] {
        // Isolated: a thread that waits inside f (for a nested loop) takes only that nested
        // loop's items, never another item of this loop, so no f(i) starts on a thread where
        // another f(j) is half done (transfer.cpp's thread_local scratch relies on that).
        tbb::this_task_arena::isolate([&] { detail::grain_loop(n, grain, f, tbb::auto_partitioner()); });
    };
    if (threads == hardware_threads())
        loop();  // the caller's own arena, shared with Embree
    else
        detail::limited_arena(threads).execute(loop);
}

}  // namespace radiosity
