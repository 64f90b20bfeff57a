// A pool of std::threads for a fixed number of jobs: figures' and sweeps' runs (app/jobs.hpp)
// and the lockstep's panes (app/lockstep.cpp). Plain threads, not OpenMP, so that
// ThreadSanitizer sees every handoff (libgomp is not instrumented).
#pragma once
#include <cstddef>
#include <functional>

namespace apiclab {

// job(0), job(1), ... on up to `threads` threads (this one included), each index once, started
// in order. Rethrows, after every thread ended, the first exception a job threw.
void run_pool(std::size_t count, int threads, const std::function<void(std::size_t)>& job);

}  // namespace apiclab
