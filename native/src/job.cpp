#include "radiosity/job.h"

#include <chrono>
#include <stdexcept>

namespace radiosity {

Job::~Job() {
    cancel();
    if (thread_.joinable()) thread_.join();
}

void Job::start(std::function<void(Control&)> work) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (running_) throw std::logic_error("a solve is already running");
        running_ = true;
        error_ = nullptr;
    }
    if (thread_.joinable()) thread_.join();
    control_.cancel.store(false);
    control_.fraction.store(0.0);
    thread_ = std::thread([this, work = std::move(work)]() {
        std::exception_ptr err;
        try {
            work(control_);
        } catch (...) {
            err = std::current_exception();
        }
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = err;
        running_ = false;
        done_cv_.notify_all();
    });
}

bool Job::running() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return running_;
}

bool Job::wait(double timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (timeout < 0) {
        done_cv_.wait(lock, [this] { return !running_; });
    } else if (!done_cv_.wait_for(lock, std::chrono::duration<double>(timeout), [this] { return !running_; })) {
        return false;
    }
    lock.unlock();
    if (thread_.joinable()) thread_.join();
    lock.lock();
    if (error_) {
        std::exception_ptr e = error_;
        error_ = nullptr;
        lock.unlock();
        std::rethrow_exception(e);
    }
    return true;
}

}  // namespace radiosity
