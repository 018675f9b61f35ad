// Internal: bounded device work (docs/RELIABILITY.md, "Device work"). A kernel over a large range
// is run as several launches over consecutive parts of it (a global offset: the kernels index with
// get_global_id, which includes it), each sized to take about 50 ms, so that
//   - no launch runs long enough for a display watchdog to reset the GPU (Windows' TDR fires at 2 s),
//   - a stop request (brdfbake/cancel.hpp) is honoured between launches, and
//   - progress can follow the parts.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>

#include "brdfbake/cancel.hpp"
#include "runtime/cl.hpp"
#include "runtime/program.hpp"

namespace brdfbake::detail {

// How long a launch should take, and how much work it may hold whatever its measured speed.
// A unit is one iteration of a kernel's inner loop (one sample, one quadrature node, one source
// point): 10 to 100 instructions and a memory read or two. The first launch holds kFirstLaunchUnits
// (well under a millisecond on a discrete GPU); each next one is sized from the speed the previous
// ones measured (event profiling) to take about kLaunchSeconds, growing at most 4x a step and never
// above kMaxLaunchUnits. A display watchdog (Windows' TDR: 2 s) is thus never approached on a GPU,
// and a stop request waits for at most one launch (about kLaunchSeconds) on any device.
inline constexpr double kLaunchSeconds = 0.05;
inline constexpr double kFirstLaunchUnits = double(1 << 22);
inline constexpr double kMaxLaunchUnits = double(1 << 30);

// Sizes successive launches of a range of `total` items of `cost` units each.
class LaunchSizer {
 public:
  LaunchSizer(double total, double cost) : cost_(std::max(cost, 1.0)), total_(total) {
    next_ = std::max(1.0, std::floor(kFirstLaunchUnits / cost_));
  }
  // Items for the next launch (at least 1).
  size_t next() const { return static_cast<size_t>(std::min(next_, total_)); }
  // After a launch of `items` that took `seconds` on the device.
  void measured(size_t items, double seconds) {
    double want = 4.0 * double(items);
    if (seconds > 0.0) want = std::min(want, double(items) * kLaunchSeconds / seconds);
    next_ = std::max(1.0, std::floor(std::min(want, kMaxLaunchUnits / cost_)));
  }

 private:
  double cost_, total_, next_;
};

// Runs items [0, items) as successive launches sized by LaunchSizer: enqueue(first, count) enqueues
// one and returns its event. Two launches are in flight at a time, so that the device never idles
// between them (the next is queued while the current runs) while a stop request is honoured within
// two launches; each launch is sized from the speed the finished ones measured. Calls
// progress(fraction) as each finishes and returns the device seconds of all of them. Throws
// Cancelled between launches (after the queued ones finish). With `min_parts` above 1, no launch
// holds more than 1 / min_parts of the items, so that a progress line moves even where the device
// is fast.
template <class Enqueue>
double launch_in_parts(size_t items, double cost, Enqueue&& enqueue, const std::function<void(double)>& progress = {},
                       size_t min_parts = 1) {
  LaunchSizer sizer(double(items), cost);
  const size_t parts = std::max<size_t>(min_parts, 1);
  const size_t cap = std::max<size_t>(1, (items + parts - 1) / parts);
  double seconds = 0.0;
  struct InFlight {
    cl::Event event;
    size_t count;
  };
  InFlight queued[2];
  size_t n_queued = 0, first = 0, done = 0;
  try {
    while (done < items) {
      while (n_queued < 2 && first < items) {
        throw_if_cancelled();
        const size_t count = std::min({sizer.next(), cap, items - first});
        queued[n_queued++] = {enqueue(first, count), count};
        first += count;
      }
      queued[0].event.wait();
      const double s = event_seconds(queued[0].event);
      seconds += s;
      sizer.measured(queued[0].count, s);
      done += queued[0].count;
      queued[0] = queued[1];
      --n_queued;
      if (progress) progress(double(done) / double(items));
    }
  } catch (...) {
    for (size_t k = 0; k < n_queued; ++k) queued[k].event.wait();  // nothing runs on after a stop
    throw;
  }
  return seconds;
}

// The same over a width x rows range of work-items: each launch is a block of whole rows, or, when
// one row is more than a launch should hold, a piece of one row. enqueue(x0, nx, y0, ny). With
// `min_parts` above 1, no launch holds more than 1 / min_parts of the rows (whole rows at least),
// so that a progress line moves even where the device is fast.
template <class Enqueue>
double launch_in_tiles(size_t width, size_t rows, double cost, Enqueue&& enqueue,
                       const std::function<void(double)>& progress = {}, size_t min_parts = 1) {
  LaunchSizer sizer(double(width) * double(rows), cost);
  const double total = double(width) * double(rows);
  const size_t part_rows = (rows + std::max<size_t>(min_parts, 1) - 1) / std::max<size_t>(min_parts, 1);
  const size_t most = std::max<size_t>(part_rows, 1) * width;
  double seconds = 0.0, done = 0.0;
  size_t x = 0, y = 0;
  while (y < rows) {
    throw_if_cancelled();
    const size_t want = std::min(sizer.next(), most);
    size_t x0 = x, nx = 0, y0 = y, ny = 1;
    if (x == 0 && want >= width) {
      nx = width;
      ny = std::min(want / width, rows - y);
      y += ny;
    } else {
      nx = std::min(want, width - x);
      x += nx;
      if (x == width) {
        x = 0;
        ++y;
      }
    }
    cl::Event e = enqueue(x0, nx, y0, ny);
    e.wait();
    const double s = event_seconds(e);
    seconds += s;
    sizer.measured(nx * ny, s);
    done += double(nx * ny);
    if (progress) progress(done / total);
  }
  return seconds;
}

// The EnqueueArgs of the block [x0, x0 + nx) x [y0, y0 + ny) of a 2-D range.
inline cl::EnqueueArgs tile_range(cl::CommandQueue& queue, size_t x0, size_t nx, size_t y0, size_t ny) {
  return cl::EnqueueArgs(queue, cl::NDRange(x0, y0), cl::NDRange(nx, ny), cl::NullRange);
}
// The same for a 1-D range of items [first, first + count).
inline cl::EnqueueArgs item_range(cl::CommandQueue& queue, size_t first, size_t count) {
  return cl::EnqueueArgs(queue, cl::NDRange(first), cl::NDRange(count), cl::NullRange);
}

// Device limits (docs/RELIABILITY.md, "Device limits"): throws RuntimeFailure naming the device
// and the limit when a buffer of `bytes` exceeds CL_DEVICE_MAX_MEM_ALLOC_SIZE, or `total` bytes
// (every buffer a bake holds at once) exceed CL_DEVICE_GLOBAL_MEM_SIZE. `what` names the data
// ("the level-0 cube of 2048^2 texels").
void check_device_memory(const Device::Impl& dev, double bytes, double total, const std::string& what);
// Throws RuntimeFailure when `kernel` cannot run work-groups of `local` items on the device
// (CL_KERNEL_WORK_GROUP_SIZE).
void check_work_group(const Device::Impl& dev, const cl::Kernel& kernel, size_t local, const std::string& what);

}  // namespace brdfbake::detail
