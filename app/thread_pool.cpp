#include "app/thread_pool.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace apiclab {

void run_pool(std::size_t count, int threads, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < count;) {
      try {
        job(i);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  const int n = std::max(1, std::min(threads, int(count)));
  for (int k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();  // this thread is one of the pool
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace apiclab
