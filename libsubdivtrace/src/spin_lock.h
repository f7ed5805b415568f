#pragma once
// A lock of one byte for objects that are many and rarely contended: a
// tile's lazy levels (two threads seldom want the same tile's next level at
// the same moment). std::mutex is 40 bytes, and a close-up caches 24,000
// tiles of 4-64 nodes each. A waiter yields its core until the holder is
// done (a level build, tens of microseconds). Not recursive.

#include <atomic>
#include <thread>

namespace subdivtrace::detail {

class SpinLock {
public:
    void lock() {
        while (locked_.exchange(true, std::memory_order_acquire))
            while (locked_.load(std::memory_order_relaxed)) std::this_thread::yield();
    }
    void unlock() { locked_.store(false, std::memory_order_release); }

private:
    std::atomic<bool> locked_{false};
};

}  // namespace subdivtrace::detail
