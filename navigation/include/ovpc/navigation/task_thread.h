// One thread that runs tasks one at a time, started by one caller who later waits for each: the
// navigator's map-and-plan cycles (Navigator::RunCyclesOnAWorkerThread) and the closed loop's share
// of the LiDAR's ray cast run on such threads.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace ovpc::navigation {

class TaskThread {
 public:
  TaskThread();
  ~TaskThread();
  TaskThread(const TaskThread&) = delete;
  TaskThread& operator=(const TaskThread&) = delete;

  /// Starts `task` on the thread; the previous task must have been waited for.
  void Start(std::function<void()> task);
  /// Waits for the task; rethrows what it threw.
  void Wait();
  /// A task is running (a hint: the answer depends on thread timing).
  bool Busy();

 private:
  void Loop();
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> task_;
  bool busy_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: started after the rest is initialised
};

}  // namespace ovpc::navigation
