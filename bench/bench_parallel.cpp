// parallel_for on oneTBB's pool (parallel.h) against what it replaced: threads started for
// every loop and joined at its end. Google Benchmark; results in bench/results/tbb_pool.md.
//
//   build/bench/bench_parallel --benchmark_repetitions=7 --benchmark_enable_random_interleaving=true \
//       --benchmark_report_aggregates_only=true
//
// ShortLoops: 10,000 loops of 100 tiny items (an incremental update is many short loops).
// LongLoop: one loop of 1,000,000 items of a few hundred ns (a full solve's link evaluation,
// roughly): the pool must not be slower where thread start-up never mattered.
// Both on all cores (threads = 0) with a grain of 16. The TBB variants beside parallel_for
// measure its parts: a limited arena kept (what threads = N below the cores uses) or made
// for every loop, the loop without this_task_arena::isolate, and simple_partitioner (every
// grain a task) instead of auto_partitioner.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "radiosity/parallel.h"

using namespace radiosity;

namespace {

// parallel.h before oneTBB (kept here as the baseline): threads started for each loop, work
// handed out in chunks of `grain` from an atomic counter.
template <class F>
void thread_per_loop_for(size_t n, int threads, F&& f, size_t grain = 64) {
    if (threads <= 0) threads = hardware_threads();
    if (n == 0) return;
    if (threads == 1 || n <= grain) {
        for (size_t i = 0; i < n; ++i) f(i);
        return;
    }
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto work = [&]() {
        try {
            for (;;) {
                size_t b = next.fetch_add(grain);
                if (b >= n) break;
                size_t e = std::min(n, b + grain);
                for (size_t i = b; i < e; ++i) f(i);
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
            next.store(n);
        }
    };
    int nt = int(std::min<size_t>(size_t(threads), (n + grain - 1) / grain));
    std::vector<std::thread> pool;
    for (int t = 1; t < nt; ++t) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();
    if (error) std::rethrow_exception(error);
}

// parallel_for's loop (parallel.h) without its arena and isolation.
template <class F, class P = const tbb::auto_partitioner>
void tbb_loop(size_t n, size_t grain, F&& f, P&& partitioner = P()) {
    detail::grain_loop(n, grain, f, partitioner);
}

enum class Way { ThreadPerLoop, Tbb, TbbKeptArena, TbbArenaPerLoop, TbbNoIsolate, TbbSimple };

constexpr size_t kGrain = 16;

// One loop of n items, each `work` square roots long, written to out.
void loop(Way way, size_t n, int work, std::vector<double>& out) {
    auto item = [&](size_t i) {
        double x = double(i);
        for (int k = 0; k < work; ++k) x = std::sqrt(x + 1.0);
        out[i] = x;
    };
    const int all = hardware_threads();
    switch (way) {
        case Way::ThreadPerLoop: thread_per_loop_for(n, 0, item, kGrain); break;
        case Way::Tbb: parallel_for(n, 0, item, kGrain); break;
        case Way::TbbKeptArena:
            detail::limited_arena(all).execute([&] { tbb::this_task_arena::isolate([&] { tbb_loop(n, kGrain, item); }); });
            break;
        case Way::TbbArenaPerLoop: {
            tbb::task_arena arena(all, 1);
            arena.execute([&] { tbb::this_task_arena::isolate([&] { tbb_loop(n, kGrain, item); }); });
            break;
        }
        case Way::TbbNoIsolate: tbb_loop(n, kGrain, item); break;
        case Way::TbbSimple:
            tbb::this_task_arena::isolate([&] { tbb_loop(n, kGrain, item, tbb::simple_partitioner()); });
            break;
    }
}

void ShortLoops(benchmark::State& state, Way way) {
    std::vector<double> out(100);
    for (auto _ : state) {
        for (int l = 0; l < 10000; ++l) loop(way, out.size(), 4, out);
        benchmark::DoNotOptimize(out.data());
    }
}

void LongLoop(benchmark::State& state, Way way) {
    std::vector<double> out(1000000);
    for (auto _ : state) {
        loop(way, out.size(), 40, out);
        benchmark::DoNotOptimize(out.data());
    }
}

}  // namespace

BENCHMARK_CAPTURE(ShortLoops, thread_per_loop, Way::ThreadPerLoop)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ShortLoops, tbb_parallel_for, Way::Tbb)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ShortLoops, tbb_kept_arena, Way::TbbKeptArena)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ShortLoops, tbb_arena_per_loop, Way::TbbArenaPerLoop)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ShortLoops, tbb_no_isolate, Way::TbbNoIsolate)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(ShortLoops, tbb_simple_partitioner, Way::TbbSimple)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(LongLoop, thread_per_loop, Way::ThreadPerLoop)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(LongLoop, tbb_parallel_for, Way::Tbb)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(LongLoop, tbb_kept_arena, Way::TbbKeptArena)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(LongLoop, tbb_simple_partitioner, Way::TbbSimple)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
