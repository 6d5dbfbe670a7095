// Minimal fork-join loop over both cores. Work is handed out in chunks from an atomic
// counter so uneven items (links with and without rays) balance themselves.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace radiosity {

int hardware_threads();

// Calls f(i) for i in [0, n) on up to `threads` threads (0 = all cores). Exceptions from f
// are re-thrown on the caller's thread after all workers stopped.
template <class F>
void parallel_for(size_t n, int threads, F&& f, size_t grain = 64) {
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

}  // namespace radiosity
