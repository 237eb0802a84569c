#pragma once
// A minimal work-sharing loop for independent cases (optimizer starts, experiment cases): each index runs exactly
// once, on one of `jobs` threads; the first exception is rethrown after all threads finish.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace softwrist {

// Runs task(i) for i in [0, count) on `jobs` threads. With `progress`, the calling thread only reports (progress(done)
// every 50 ms and at the end) while `jobs` worker threads run.
template <typename Task>
void parallel_for(int count, int jobs, Task&& task, const std::function<void(int)>& progress = {}) {
  if (count <= 0) return;
  std::atomic<int> next{0}, done{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&] {
    for (int i = next++; i < count; i = next++) {
      try {
        task(i);
      } catch (...) {
        std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
      ++done;
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < std::clamp(jobs, 1, count); ++j) threads.emplace_back(worker);
  if (progress) {
    std::thread reporter_work(worker);
    int reported = -1;
    while (done < count) {
      if (done != reported) progress(reported = done);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    reporter_work.join();
    progress(count);
  } else {
    worker();
  }
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace softwrist
