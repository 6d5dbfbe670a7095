// A background job on a native thread, so Blender's main thread can poll progress from a
// timer or modal operator (Python threads inside Blender are unsupported).
#pragma once
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "radiosity/solver.h"

namespace radiosity {

class Job {
public:
    ~Job();
    // Runs work(control) on a new thread; throws std::logic_error if one is running.
    void start(std::function<void(Control&)> work);
    bool running() const;
    double progress() const { return control_.fraction.load(); }
    void cancel() { control_.cancel.store(true); }
    // Waits up to timeout seconds (negative: forever). True when finished; then re-throws
    // the job's exception, if any, once.
    bool wait(double timeout_seconds);

private:
    Control control_;
    std::thread thread_;
    mutable std::mutex mutex_;
    std::condition_variable done_cv_;
    bool running_ = false;
    std::exception_ptr error_;
};

}  // namespace radiosity
