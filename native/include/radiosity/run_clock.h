// RunClock: the timing of one run of the solver (a full solve or an update): when it started,
// and its phase laps, each adding the time and the rays cast since the lap before to the
// phase's entries in Stats::phases and Stats::phase_rays. A run makes its own and drops it at
// its end, so no timing carries over from one run to the next. Its seconds_since is the timer
// the solver's other timings share.
#pragma once
#include <chrono>
#include <cstdint>

#include "radiosity/stats.h"

namespace radiosity {

class RunClock {
public:
    using Clock = std::chrono::steady_clock;

    // Seconds from `t` to now: the one timer of the solver's phases.
    static double seconds_since(Clock::time_point t) {
        return std::chrono::duration<double>(Clock::now() - t).count();
    }

    // A run starting now, with `rays` cast so far by the Visibility whose count the laps read.
    explicit RunClock(int64_t rays) : start_(Clock::now()), lap_t_(start_), lap_rays_(rays) {}

    // Seconds since the run started.
    double seconds() const { return seconds_since(start_); }

    // Ends a timed phase: the time since the last lap (or the start) and the rays cast since
    // (`rays`: the count now) are added to `phase`'s entries of `stats`, new entries appended
    // in the order phases first end.
    void lap(Stats& stats, const char* phase, int64_t rays) {
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - lap_t_).count();
        lap_t_ = now;
        const int64_t dr = rays - lap_rays_;
        lap_rays_ = rays;
        for (size_t i = 0; i < stats.phases.size(); ++i)
            if (stats.phases[i].first == phase) {
                stats.phases[i].second += dt;
                stats.phase_rays[i].second += dr;
                return;
            }
        stats.phases.emplace_back(phase, dt);
        stats.phase_rays.emplace_back(phase, dr);
    }

private:
    Clock::time_point start_;
    Clock::time_point lap_t_;  // the last lap (or the start)
    int64_t lap_rays_;         // rays cast at lap_t_
};

}  // namespace radiosity
