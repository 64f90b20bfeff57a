// The one wall clock of app/: seconds on a monotonic clock, for timings and progress.
#pragma once
#include <chrono>

namespace apiclab {

inline double now_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace apiclab
