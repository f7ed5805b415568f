#pragma once
// Construction work spread over the machine's cores (the base records'
// chunks, the top-level BVH's halves): the one place the library starts
// threads of its own.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace subdivtrace::detail {

/// Runs work(i, state) for every i in [0, count) on up to one thread per core
/// (the caller's among them), each thread with its own default-constructed
/// State. Once every thread has stopped, rethrows the first exception; the
/// other threads finish their current item and take no more.
template <class State, class Work>
void run_in_parallel(std::size_t count, Work work) {
    const std::size_t threads =
        std::min<std::size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto worker = [&] {
        try {
            State state;
            for (std::size_t i; (i = next.fetch_add(1)) < count;) work(i, state);
        } catch (...) {
            const std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next = count;
        }
    };
    std::vector<std::thread> pool;
    try {
        for (std::size_t k = 1; k < threads; ++k) pool.emplace_back(worker);
    } catch (...) {
        // No more threads to be had: the items run on those already started.
    }
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace subdivtrace::detail
