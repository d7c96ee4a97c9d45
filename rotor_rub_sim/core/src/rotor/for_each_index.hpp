// Independent pieces of an analysis (the Campbell diagram's speeds, the
// critical-speed search's grid) on the machine's cores.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace rotor_rub::core {

// Runs f(i) once for every i in [0, count) on up to `jobs` threads (the
// caller's among them); f must write only what index i owns, so the results
// are the same at any number of jobs (FeRotor.CampbellIsTheSameAtAnyJobs).
// The first exception f throws is rethrown once every thread has ended; the
// indices not yet started are skipped (ForEachIndex.AFailureOnAThreadReachesTheCaller).
template <class F>
void for_each_index(int count, unsigned jobs, const F& f) {
  const unsigned threads = std::min(std::max(jobs, 1u), static_cast<unsigned>(std::max(count, 1)));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (int i = next++; i < count; i = next++) {
      try {
        f(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = count;
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) {
    try {
      pool.emplace_back(worker);
    } catch (const std::system_error&) {
      break;  // no more threads: those started, and this one, take every index
    }
  }
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace rotor_rub::core
