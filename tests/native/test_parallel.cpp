// parallel_for on oneTBB (parallel.h): every item once, the thread limit, exceptions, nested
// loops, and solutions that do not depend on the number of threads or the schedule.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "radiosity/job.h"
#include "radiosity/parallel.h"
#include "test_util.h"

using namespace radiosity;

namespace {

// The most bodies seen running at once.
struct Concurrency {
    std::atomic<int> now{0}, most{0};
    void enter() {
        const int n = ++now;
        int m = most.load();
        while (n > m && !most.compare_exchange_weak(m, n)) {
        }
    }
    void leave() { --now; }
};

void sleepy(Concurrency& c) {
    c.enter();
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    c.leave();
}

struct Numbered : std::runtime_error {
    explicit Numbered(size_t i) : std::runtime_error("item " + std::to_string(i)), item(i) {}
    size_t item;
};

}  // namespace

TEST(Parallel, EveryItemRunsExactlyOnce) {
    const size_t n = 100003;
    for (int threads : {0, 1, 2, 3}) {
        for (size_t grain : {size_t(0), size_t(1), size_t(7), size_t(64), size_t(4096), n + 1}) {
            std::unique_ptr<std::atomic<int>[]> seen(new std::atomic<int>[n]);
            for (size_t i = 0; i < n; ++i) seen[i] = 0;
            parallel_for(n, threads, [&](size_t i) { ++seen[i]; }, grain);
            size_t wrong = 0;
            for (size_t i = 0; i < n; ++i) wrong += seen[i] != 1;
            EXPECT_EQ(wrong, 0u) << "threads " << threads << " grain " << grain;
        }
    }
    parallel_for(0, 0, [](size_t) { FAIL() << "no item in an empty loop"; });
}

TEST(Parallel, OneThreadRunsOnTheCaller) {
    const auto caller = std::this_thread::get_id();
    int others = 0;  // a plain int: one thread only
    parallel_for(10000, 1, [&](size_t) { others += std::this_thread::get_id() != caller; }, 1);
    EXPECT_EQ(others, 0);
}

TEST(Parallel, ThreadLimitIsHonoured) {
    // Raise TBB's global cap over the cores, so that only parallel_for's own limit stops a
    // loop from running wider (else on a 2-core machine every limit would hold trivially).
    tbb::global_control wide(tbb::global_control::max_allowed_parallelism, size_t(std::max(8, hardware_threads() + 4)));
    for (int threads = 1; threads <= hardware_threads() + 1; ++threads) {
        Concurrency c;
        parallel_for(400, threads, [&](size_t) { sleepy(c); }, 1);
        EXPECT_LE(c.most.load(), std::min(threads, hardware_threads())) << "threads " << threads;
    }
    // The arena behind a limit below the cores, at a limit this machine can show.
    Concurrency c;
    detail::limited_arena(3).execute([&] { tbb::parallel_for(size_t(0), size_t(400), [&](size_t) { sleepy(c); }); });
    EXPECT_LE(c.most.load(), 3);
    std::printf("[ figure ] most items at once in an arena of 3: %d\n", c.most.load());
    EXPECT_EQ(&detail::limited_arena(3), &detail::limited_arena(3)) << "an arena per limit, kept";
}

TEST(Parallel, ExceptionTypeAndItemReachTheCaller) {
    for (int threads : {1, 0}) {
        try {
            parallel_for(100000, threads, [&](size_t i) {
                if (i == 4321) throw Numbered(i);
            }, 16);
            ADD_FAILURE() << "no exception, threads " << threads;
        } catch (const Numbered& e) {
            EXPECT_EQ(e.item, 4321u);
        }
    }
}

TEST(Parallel, FirstExceptionCancelsTheRestAndAllStopBeforeTheCallerGoesOn) {
    // Many items throw; one exception (one of theirs) reaches the caller, after no body runs
    // any more, and the items not yet begun are skipped (cancelled), not run: each item
    // started after the first throw sleeps, so a loop that went on would take minutes.
    const size_t n = 1000000;
    std::atomic<int> running{0}, after_throw{0};
    std::atomic<bool> thrown{false};
    try {
        parallel_for(n, 0, [&](size_t i) {
            ++running;
            if (thrown.load()) {
                ++after_throw;
                std::this_thread::sleep_for(std::chrono::microseconds(200));
            }
            if (i % 1000 == 999) {
                thrown = true;
                --running;
                throw Numbered(i);
            }
            --running;
        }, 16);
        ADD_FAILURE() << "no exception";
    } catch (const Numbered& e) {
        EXPECT_EQ(e.item % 1000, 999u);
    }
    EXPECT_EQ(running.load(), 0) << "a body still ran when the exception reached the caller";
    EXPECT_LT(after_throw.load(), 2000) << "items went on after the first exception";
    std::printf("[ figure ] items begun after the first exception: %d\n", after_throw.load());
}

TEST(Parallel, NestedLoopsNeverStartAnOuterItemInsideAnother) {
    // transfer.cpp's thread_local scratch is in use for the whole of one item: an outer item
    // waiting for its inner loop must not pick up another outer item on the same thread.
    // That takes more than two threads to happen (measured: without this_task_arena::isolate
    // a few outer items of 64 start inside another in 8 threads, none in 2), so the loops run
    // in an arena of 8 whatever the cores.
    tbb::global_control wide(tbb::global_control::max_allowed_parallelism, 8);
    thread_local int depth = 0;
    std::atomic<int> reentered{0};
    for (int run = 0; run < 5; ++run) {
        std::vector<long> sums(64, 0);
        detail::limited_arena(8).execute([&] {
            parallel_for(sums.size(), 0, [&](size_t i) {
                if (++depth != 1) ++reentered;
                std::vector<long> part(20, 0);
                parallel_for(part.size(), 0, [&](size_t k) {
                    part[k] = long(i * k);
                    std::this_thread::sleep_for(std::chrono::microseconds(20));
                }, 1);
                for (long v : part) sums[i] += v;
                --depth;
            }, 1);
        });
        for (size_t i = 0; i < sums.size(); ++i) ASSERT_EQ(sums[i], long(i) * 19 * 20 / 2);
    }
    EXPECT_EQ(reentered.load(), 0);
}

TEST(Parallel, SolutionsDoNotDependOnThreadsOrSchedule) {
    // A solve and an incremental update (with the final gather), bit for bit the same on one
    // thread, on all cores twice, and inside a background job (the binding's async bake).
    std::vector<float> ref;
    for (int run = 0; run < 4; ++run) {
        Settings st = Settings::preset("DRAFT");
        st.threads = run == 0 ? 1 : 0;
        st.gather_rays = 16;
        Solver s(scenes::box_room(4), st);
        std::vector<float> got;
        auto work = [&](Control* control) {
            s.solve(control);
            s.move_object(2, radiosity::testing::translation(Vec3{10, 15, 0}));
            s.update(control);
            got = s.all_corner_radiance();
        };
        if (run == 3) {
            Job job;
            job.start([&](Control& c) { work(&c); });
            ASSERT_TRUE(job.wait(-1));
        } else {
            work(nullptr);
        }
        if (run == 0)
            ref = got;
        else
            EXPECT_TRUE(got == ref) << "run " << run << " differs from the one-thread run";
    }
}
