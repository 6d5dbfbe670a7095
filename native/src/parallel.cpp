#include "radiosity/parallel.h"

#include <map>
#include <memory>
#include <mutex>

#include <tbb/info.h>

namespace radiosity {

int hardware_threads() {
    static const int n = tbb::info::default_concurrency();
    return n < 1 ? 1 : n;
}

namespace detail {

tbb::task_arena& limited_arena(int threads) {
    // Never destroyed: an arena is kept for the life of the process, and a loop may still run
    // in one while static destructors run (a job thread at exit). Reachable from this pointer,
    // so LeakSanitizer does not count it.
    struct Cache {
        std::mutex mutex;
        std::map<int, std::unique_ptr<tbb::task_arena>> arenas;
    };
    static Cache* const cache = new Cache;
    std::lock_guard<std::mutex> lock(cache->mutex);
    auto& a = cache->arenas[threads];
    if (!a) {
        // One slot reserved for the thread that calls execute, the rest for TBB's workers.
        a = std::make_unique<tbb::task_arena>(threads, 1);
        a->initialize();
    }
    return *a;
}

}  // namespace detail
}  // namespace radiosity
